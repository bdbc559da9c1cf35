#include "bcassim/atlas/LigamentAtlasFile.h"

#include <fmt/format.h>
#include <fmt/os.h>

#include <cmath>
#include <filesystem>
#include <fstream>

#include "bcassim/Error.h"
#include "bcassim/io/CsvTable.h"
#include "bcassim/io/MeshWriter.h"
#include "bcassim/io/PointCsvWriter.h"
#include "bcassim/io/SurfaceReader.h"

namespace bcassim {
namespace {
namespace fs = std::filesystem;

std::ofstream openOut(const fs::path& p) {
  std::ofstream f(p);
  if (!f) throw OutputError(fmt::format("{}: cannot write", p.string()));
  f.precision(17);
  return f;
}

int col(const CsvTable& t, const std::string& file, const std::string& name) {
  const int c = t.column(name);
  if (c < 0) throw InputError(fmt::format("{}: expected a column '{}'", file, name));
  return c;
}

void writeAttachment(std::ofstream& f, const SurfaceAttachment& a, Eigen::Index i) {
  for (int k = 0; k < 3; ++k) f << ',' << a.corners()(i, k);
  for (int k = 0; k < 3; ++k) f << ',' << a.weights()(i, k);
}

SurfaceAttachment readAttachment(const CsvTable& t, const std::string& file,
                                 const std::string& prefix, Eigen::Index nv) {
  const Eigen::Index n = t.rows.rows();
  Eigen::MatrixX3i c(n, 3);
  Eigen::MatrixX3d w(n, 3);
  for (int k = 0; k < 3; ++k) {
    const int cv = col(t, file, fmt::format("{}_v{}", prefix, k));
    const int cw = col(t, file, fmt::format("{}_w{}", prefix, k));
    for (Eigen::Index i = 0; i < n; ++i) {
      const double v = t.rows(i, cv);
      if (v < 0 || v >= static_cast<double>(nv) || v != std::floor(v)) {
        throw InputError(
            fmt::format("{}:{}: {}_v{} must be a vertex index of the template "
                        "(0..{}), got {}",
                        file, t.lines[i], prefix, k, nv - 1, v));
      }
      c(i, k) = static_cast<int>(v);
      w(i, k) = t.rows(i, cw);
    }
  }
  return SurfaceAttachment(c, w);
}
}  // namespace

void writeLigamentAtlas(const std::string& dirName, const LigamentAtlas& a) {
  const fs::path dir(dirName);
  fs::create_directories(dir);
  writeSurface((dir / "template.obj").string(), a.templ);
  {
    std::ofstream f = openOut(dir / "planes.csv");
    f << "radial,cx,cy,cz,ax,ay,az,rx,ry,rz,parameter\n";
    const CuttingPlaneFamily& p = a.curve.planes;
    for (const CuttingPlane& q : p.planes) {
      f << (p.kind == CuttingPlaneFamily::Kind::Radial ? 1 : 0);
      for (const Eigen::Vector3d* v : {&p.centre, &p.axis, &p.reference})
        for (int k = 0; k < 3; ++k) f << ',' << (*v)(k);
      f << ',' << q.parameter << '\n';
    }
  }
  {
    std::ofstream f = openOut(dir / "curve.csv");
    f << "plane,count,sigma";
    for (const char* s : {"mean", "lower", "upper"}) {
      for (int k = 0; k < 3; ++k) f << ',' << s << "_v" << k;
      for (int k = 0; k < 3; ++k) f << ',' << s << "_w" << k;
    }
    f << '\n';
    for (Eigen::Index i = 0; i < a.curve.mean.size(); ++i) {
      f << a.curve.plane[i] << ',' << a.curve.count[i] << ',' << a.curve.sigma(i);
      writeAttachment(f, a.curve.mean, i);
      writeAttachment(f, a.curve.lower, i);
      writeAttachment(f, a.curve.upper, i);
      f << '\n';
    }
  }
  if (a.templRidge.rows() > 0) {
    std::ofstream f = openOut(dir / "template_ridge.csv");
    f << "v0,v1\n";
    for (Eigen::Index e = 0; e < a.templRidge.rows(); ++e)
      f << a.templRidge(e, 0) << ',' << a.templRidge(e, 1) << '\n';
  }
  writePointSetsCsv((dir / "carried_curves.csv").string(), "subject", a.carriedCurves);
  {
    std::ofstream f = openOut(dir / "subjects.csv");
    f << "subject,name,alignment_rms_m,data\n";
    for (size_t s = 0; s < a.subjects.size(); ++s)
      f << s << ',' << a.subjects[s] << ',' << (s < a.alignmentRms.size() ? a.alignmentRms[s] : 0.0)
        << ',' << (s < a.data.size() ? a.data[s] : 0.0) << '\n';
  }
}

LigamentAtlas readLigamentAtlas(const std::string& dirName) {
  const fs::path dir(dirName);
  if (!fs::is_directory(dir)) {
    throw InputError(
        fmt::format("{}: expected an atlas folder (from 'bcassim atlas build')", dirName));
  }
  LigamentAtlas a;
  const fs::path tp = dir / "template.obj";
  if (!fs::exists(tp)) throw InputError(fmt::format("{}: missing (atlas template)", tp.string()));
  a.templ = readSurface(tp.string());
  const fs::path rp = dir / "template_ridge.csv";
  if (fs::exists(rp)) {
    const std::string rf = rp.string();
    const CsvTable rt = readCsvTable(rf);
    const int c0 = col(rt, rf, "v0"), c1 = col(rt, rf, "v1");
    a.templRidge.resize(rt.rows.rows(), 2);
    const auto nv = static_cast<double>(a.templ.V.rows());
    for (Eigen::Index i = 0; i < rt.rows.rows(); ++i) {
      for (const int c : {c0, c1}) {
        const double v = rt.rows(i, c);
        if (!(v >= 0 && v < nv) || v != std::floor(v)) {
          throw InputError(
              fmt::format("{}:{}: expected a vertex index of the template, 0..{}, got {}", rf,
                          rt.lines[i], a.templ.V.rows() - 1, v));
        }
      }
      a.templRidge(i, 0) = static_cast<int>(rt.rows(i, c0));
      a.templRidge(i, 1) = static_cast<int>(rt.rows(i, c1));
    }
  }
  const std::string pf = (dir / "planes.csv").string();
  const CsvTable pt = readCsvTable(pf);
  if (pt.rows.rows() == 0) throw InputError(fmt::format("{}: expected at least one plane", pf));
  auto vec = [&](const char* x, const char* y, const char* z) {
    return Eigen::Vector3d(pt.rows(0, col(pt, pf, x)), pt.rows(0, col(pt, pf, y)),
                           pt.rows(0, col(pt, pf, z)));
  };
  const Eigen::Vector3d centre = vec("cx", "cy", "cz"), axis = vec("ax", "ay", "az"),
                        ref = vec("rx", "ry", "rz");
  std::vector<double> params;
  const int cp = col(pt, pf, "parameter");
  for (Eigen::Index i = 0; i < pt.rows.rows(); ++i) params.push_back(pt.rows(i, cp));
  a.curve.planes = pt.rows(0, col(pt, pf, "radial")) != 0.0
                       ? radialPlanes(centre, axis, ref, params)
                       : parallelPlanes(centre, axis, params);
  const std::string cf = (dir / "curve.csv").string();
  const CsvTable ct = readCsvTable(cf);
  if (ct.rows.rows() == 0)
    throw InputError(fmt::format("{}: expected at least one curve point", cf));
  const int cpl = col(ct, cf, "plane"), ccount = col(ct, cf, "count"), csig = col(ct, cf, "sigma");
  a.curve.sigma.resize(ct.rows.rows());
  for (Eigen::Index i = 0; i < ct.rows.rows(); ++i) {
    const double p = ct.rows(i, cpl);
    if (p < 0 || p >= static_cast<double>(params.size())) {
      throw InputError(
          fmt::format("{}:{}: plane must be 0..{}, got {}", cf, ct.lines[i], params.size() - 1, p));
    }
    a.curve.plane.push_back(static_cast<int>(p));
    a.curve.count.push_back(static_cast<int>(ct.rows(i, ccount)));
    a.curve.sigma(i) = ct.rows(i, csig);
  }
  const Eigen::Index nv = a.templ.V.rows();
  a.curve.mean = readAttachment(ct, cf, "mean", nv);
  a.curve.lower = readAttachment(ct, cf, "lower", nv);
  a.curve.upper = readAttachment(ct, cf, "upper", nv);
  const fs::path sp = dir / "carried_curves.csv";
  if (fs::exists(sp)) {
    const CsvTable st = readCsvTable(sp.string());
    const int cs = col(st, sp.string(), "subject"), cx = col(st, sp.string(), "x"),
              cy = col(st, sp.string(), "y"), cz = col(st, sp.string(), "z");
    for (Eigen::Index i = 0; i < st.rows.rows(); ++i) {
      const auto s = static_cast<size_t>(st.rows(i, cs));
      if (a.carriedCurves.size() <= s) a.carriedCurves.resize(s + 1);
      Eigen::MatrixX3d& c = a.carriedCurves[s];
      c.conservativeResize(c.rows() + 1, 3);
      c.row(c.rows() - 1) << st.rows(i, cx), st.rows(i, cy), st.rows(i, cz);
    }
  }
  return a;
}

void writeCarriedCurveFiles(const std::string& folder, const TriMesh& surface,
                            const CarriedCurve& c) {
  const fs::path dir(folder);
  writeSurface((dir / "surface.vtp").string(), surface);
  writeSurface((dir / "surface.obj").string(), surface);
  writePointsCsv((dir / "mean_curve.csv").string(), c.mean, {{"sigma", c.sigma}});
  writePointsCsv((dir / "band_lower.csv").string(), c.lower);
  writePointsCsv((dir / "band_upper.csv").string(), c.upper);
  FieldSet f;
  f.pointScalars.push_back({"sigma_m", c.sigma});
  writePolyline((dir / "mean_curve.vtp").string(), c.mean, f);
  writePolyline((dir / "band_lower.vtp").string(), c.lower);
  writePolyline((dir / "band_upper.vtp").string(), c.upper);
}

}  // namespace bcassim
