#include "bcassim/atlas/AnnotatedLivers.h"

#include <fmt/format.h>

#include <algorithm>
#include <filesystem>

#include "bcassim/Error.h"
#include "bcassim/io/SurfaceReader.h"
#include "bcassim/ligaments/AttachmentCurve.h"
#include "bcassim/ligaments/EsegLabels.h"

namespace bcassim {

namespace fs = std::filesystem;

LiverFolder readAnnotatedLivers(const std::string& dir, int label, double scale, int ridgeLabel) {
  if (!fs::is_directory(dir)) {
    throw InputError(fmt::format("{}: expected a folder of NAME.obj + NAME.eseg livers", dir));
  }
  std::vector<fs::path> objs;
  for (const auto& e : fs::directory_iterator(dir))
    if (e.path().extension() == ".obj") objs.push_back(e.path());
  std::sort(objs.begin(), objs.end());
  LiverFolder out;
  for (const fs::path& obj : objs) {
    const std::string name = obj.stem().string();
    fs::path eseg = obj;
    eseg.replace_extension(".eseg");
    if (!fs::exists(eseg)) {
      out.skipped.push_back(name + ": no .eseg beside it");
      continue;
    }
    try {
      const TriMesh m = readSurface(obj.string());
      const LabelledEdges e = readEseg(eseg.string(), m);
      // Pieces of the annotation farther than 30 mm from the main one are stray labels.
      const AttachmentCurve c = extractAttachmentCurve(m, e, label, eseg.string(), 30.0e-3 / scale);
      if (c.points.rows() < 2) {
        out.skipped.push_back(name + ": the labelled curve has fewer than 2 points");
        continue;
      }
      out.subjects.push_back({name, TriMesh{m.V * scale, m.F}, c.points * scale,
                              edgesLabelled(e, ridgeLabel), edgesLabelled(e, label)});
    } catch (const InputError& err) {
      out.skipped.push_back(name + ": " + err.what());
    }
  }
  return out;
}

}  // namespace bcassim
