#include "bcassim/mechanics/TetElasticity.h"

#include <fmt/format.h>

#include <algorithm>
#include <array>

#include "bcassim/Error.h"
#include "bcassim/mechanics/ElementKernels.h"

namespace bcassim {
namespace {

// Deformation gradient F = sum_a x_a (grad N_a)^T of tet t (eq. 2.7).
inline Mat3 deformationGradient(const Eigen::VectorXd& x, const Eigen::Vector4i& tet,
                                const Eigen::Matrix<double, 4, 3>& gradN) {
  Mat3 F = Mat3::Zero();
  for (int a = 0; a < 4; ++a) F.noalias() += x.segment<3>(3 * tet(a)) * gradN.row(a);
  return F;
}

// The split psi(F) = psi_dev(F) + lambda/2 theta(F)^2 that mean dilatation needs: psi_dev is the
// same law with lambda = 0, theta its volumetric measure. Only declared for the laws written so.
template <class M>
struct VolumetricSplit;

template <>
struct VolumetricSplit<StvkMaterial> {  // theta = tr E = (|F|^2 - 3)/2
  static StvkMaterial deviatoric(const StvkMaterial& m) { return {0.0, m.mu}; }
  static double theta(const Mat3& F) { return 0.5 * (F.squaredNorm() - 3.0); }
  static Mat3 dTheta(const Mat3& F) { return F; }
  // K_ab += c (d2 theta/dF2 contracted with gradN_a, gradN_b) = c (gNa.gNb) I.
  static void addHessian(const Mat3&, const ShapeGradients& G, double c, Mat12& K) {
    const Eigen::Matrix4d GG = c * G * G.transpose();
    for (int a = 0; a < 4; ++a)
      for (int b = 0; b < 4; ++b) K.block<3, 3>(3 * a, 3 * b).diagonal().array() += GG(a, b);
  }
};

template <>
struct VolumetricSplit<NeoHookeanMaterial> {  // theta = ln J
  static NeoHookeanMaterial deviatoric(const NeoHookeanMaterial& m) { return {0.0, m.mu}; }
  static double theta(const Mat3& F) { return std::log(F.determinant()); }
  static Mat3 dTheta(const Mat3& F) { return F.inverse().transpose(); }
  // d(F^-T) = -F^-T dF^T F^-T, so with q_a = F^-T gradN_a: K_ab += -c q_b q_a^T.
  static void addHessian(const Mat3& F, const ShapeGradients& G, double c, Mat12& K) {
    const Eigen::Matrix<double, 3, 4> q = F.inverse().transpose() * G.transpose();
    for (int a = 0; a < 4; ++a)
      for (int b = 0; b < 4; ++b)
        K.block<3, 3>(3 * a, 3 * b) -= c * q.col(b) * q.col(a).transpose();
  }
};

template <class M>
constexpr bool hasVolumetricSplit = requires {
  VolumetricSplit<M>::theta(Mat3());
};

// The tets with det F <= 0 one evaluation met under a law that takes no inverted state (every
// law but the linear one, see HyperelasticMaterial.h): how many, the first and its det F.
struct InvertedTets {
  Eigen::Index count = 0, first = -1;
  double detF = 0.0;
  void add(Eigen::Index t, double J) {
    if (count++ == 0) {
      first = t;
      detF = J;
    }
  }
  // Counts tet t at F if its law M takes no inverted state and det F <= 0.
  template <class M>
  void check(Eigen::Index t, const Mat3& F) {
    if constexpr (!M::acceptsInverted)
      if (const double J = F.determinant(); J <= 0) add(t, J);
  }
  // Those of a later part of the same loop (the first of this stays first).
  void merge(const InvertedTets& later) {
    if (later.count == 0) return;
    if (count == 0) {
      first = later.first;
      detF = later.detF;
    }
    count += later.count;
  }
  void throwIfAny() const {
    if (count > 0) throw InvertedElementError(first, detF, count);
  }
};

// Adds the internal forces of tets [first, last) of `tets` (all of law `material`) at x to f,
// counting the inverted ones.
template <class Law>
void addTetForces(const Law& material, const std::vector<int>& tets, Eigen::Index first,
                  Eigen::Index last, const Eigen::MatrixX4i& T,
                  const std::vector<Eigen::Matrix<double, 4, 3>>& gradN,
                  const std::vector<double>& volume, const Eigen::VectorXd& x, Eigen::VectorXd& f,
                  InvertedTets& inverted) {
  for (Eigen::Index i = first; i < last; ++i) {
    const int t = tets[static_cast<size_t>(i)];
    const Eigen::Vector4i tet = T.row(t);
    const Mat3 F = deformationGradient(x, tet, gradN[t]);
    inverted.check<Law>(t, F);
    const Eigen::Matrix<double, 3, 4> H = volume[t] * material.pk1(F) * gradN[t].transpose();
    for (int a = 0; a < 4; ++a) f.segment<3>(3 * tet(a)) += H.col(a);
  }
}

}  // namespace

TetElasticity::TetElasticity(const TetMesh& mesh, std::vector<Material> regionMaterials,
                             int meanDilatationPatchTets)
    : T_(mesh.T), materials_(std::move(regionMaterials)) {
  if (materials_.empty()) throw InputError("elasticity: no material given");
  const Eigen::Index nt = mesh.numTets();
  gradN_.resize(nt);
  volume_.resize(nt);
  tetsOfRegion_.resize(materials_.size());
  for (Eigen::Index t = 0; t < nt; ++t) {
    Mat3 Dm;
    for (int k = 0; k < 3; ++k)
      Dm.col(k) = (mesh.V.row(T_(t, k + 1)) - mesh.V.row(T_(t, 0))).transpose();
    const double det = Dm.determinant();
    if (!(det > 0))
      throw InputError(
          fmt::format("elasticity: tet {} has non-positive rest volume {:.3g} m^3", t, det / 6.0));
    volume_[t] = det / 6.0;
    const Mat3 DmInv = Dm.inverse();
    // grad N_{1..3} are the rows of Dm^-1; grad N_0 = -(sum of the others).
    gradN_[t].block<3, 3>(1, 0) = DmInv;
    gradN_[t].row(0) = -DmInv.colwise().sum();
    const int r = materials_.size() == 1 ? 0 : mesh.regionOf(t);
    if (r < 0 || r >= static_cast<int>(materials_.size()))
      throw InputError(
          fmt::format("elasticity: tet {} is in region {} but {} region materials are "
                      "defined",
                      t, r, materials_.size()));
    tetsOfRegion_[r].push_back(static_cast<int>(t));
    if (materials_.size() > 1) regionOfTet_.push_back(r);
  }
  if (meanDilatationPatchTets != 1) {
    for (const Material& m : materials_)
      std::visit(
          [](const auto& law) {
            if constexpr (!hasVolumetricSplit<std::decay_t<decltype(law)>>)
              throw InputError(
                  fmt::format("material '{}' has no volumetric split for mean "
                              "dilatation; expected stvk or neohookean",
                              law.name()));
          },
          m);
    patches_ = std::make_shared<const MeanDilatationPatches>(
        makeMeanDilatationPatches(mesh, meanDilatationPatchTets));
    patchesOfRegion_.resize(materials_.size());
    for (int p = 0; p < patches_->numPatches(); ++p) {
      const int t = patches_->tets[p].front();
      patchesOfRegion_[materials_.size() == 1 ? 0 : mesh.regionOf(t)].push_back(p);
    }
  }
}

const std::vector<std::vector<int>>& TetElasticity::patchNodeSets() const {
  static const std::vector<std::vector<int>> none;
  return patches_ ? patches_->nodes : none;
}

// Calls visit(material, tets) once per region with the concrete material type, so the per-tet
// loops inside are compiled for each material without dispatch in the hot path.
template <class Visitor>
void TetElasticity::forEachRegion(Visitor&& visit) const {
  for (size_t r = 0; r < materials_.size(); ++r)
    std::visit([&](const auto& m) { visit(m, tetsOfRegion_[r]); }, materials_[r]);
}

double TetElasticity::energy(const Eigen::VectorXd& x) const {
  if (patches_) return patchEnergy(x);
  double W = 0.0;
  forEachRegion([&](const auto& material, const std::vector<int>& tets) {
    for (int t : tets) {
      const Eigen::Vector4i tet = T_.row(t);
      W += volume_[t] * material.energy(deformationGradient(x, tet, gradN_[t]));
    }
  });
  return W;
}

// Calls visit(t) for each tet whose law takes no inverted state, in mesh order (so that the first
// inverted tet reported is the lowest index, whatever the regions).
template <class Visitor>
void TetElasticity::forEachTetThatMustNotInvert(Visitor&& visit) const {
  std::vector<bool> mustNotInvert(materials_.size());
  for (size_t r = 0; r < materials_.size(); ++r)
    mustNotInvert[r] = std::visit(
        [](const auto& m) { return !std::decay_t<decltype(m)>::acceptsInverted; }, materials_[r]);
  if (std::find(mustNotInvert.begin(), mustNotInvert.end(), true) == mustNotInvert.end()) return;
  for (Eigen::Index t = 0; t < T_.rows(); ++t)
    if (mustNotInvert[regionOfTet_.empty() ? 0 : regionOfTet_[t]]) visit(t);
}

Eigen::Index TetElasticity::countInverted(const Eigen::VectorXd& x) const {
  Eigen::Index inverted = 0;
  forEachTetThatMustNotInvert([&](Eigen::Index t) {
    const Eigen::Vector4i tet = T_.row(t);
    if (deformationGradient(x, tet, gradN_[t]).determinant() <= 0) ++inverted;
  });
  return inverted;
}

// det F = det(D_s) / det(D_m) with D_s, D_m the deformed and rest edge matrices and
// det(D_m) = 6 V > 0: the sign is that of the triple product of the deformed edges.
void TetElasticity::requireNoInverted(const Eigen::VectorXd& x) const {
  InvertedTets inverted;
  forEachTetThatMustNotInvert([&](Eigen::Index t) {
    const Vec3 x0 = x.segment<3>(3 * T_(t, 0));
    const double det =
        (x.segment<3>(3 * T_(t, 1)) - x0)
            .dot((x.segment<3>(3 * T_(t, 2)) - x0).cross(x.segment<3>(3 * T_(t, 3)) - x0));
    if (det <= 0) inverted.add(t, det / (6.0 * volume_[t]));
  });
  inverted.throwIfAny();
}

void TetElasticity::addInternalForces(const Eigen::VectorXd& x, Eigen::VectorXd& f) const {
  if (patches_) return addPatchForcesAndStiffness(x, nullptr, 1.0, f, nullptr);
  InvertedTets inverted;
  forEachRegion([&](const auto& material, const std::vector<int>& tets) {
    addTetForces(material, tets, 0, static_cast<Eigen::Index>(tets.size()), T_, gradN_, volume_, x,
                 f, inverted);
  });
  inverted_ = inverted.count;
  inverted.throwIfAny();
}

void TetElasticity::addInternalForces(const Eigen::VectorXd& x, Eigen::VectorXd& f,
                                      ChunkedForces& chunks) const {
  if (patches_) return addInternalForces(x, f);
  InvertedTets inverted;
  chunks.begin(f.size());
  forEachRegion([&](const auto& material, const std::vector<int>& tets) {
    std::array<InvertedTets, ChunkedForces::kChunks> found;
    chunks.forEachChunk(static_cast<Eigen::Index>(tets.size()),
                        [&](int c, Eigen::Index first, Eigen::Index last, Eigen::VectorXd& out) {
                          addTetForces(material, tets, first, last, T_, gradN_, volume_, x, out,
                                       found[static_cast<size_t>(c)]);
                        });
    for (const InvertedTets& chunk : found) inverted.merge(chunk);  // in element order
  });
  chunks.addTo(f);
  inverted_ = inverted.count;
  inverted.throwIfAny();
}

void TetElasticity::addForcesAndStiffness(const Eigen::VectorXd& x, const AssemblyPattern& pattern,
                                          double scale, Eigen::VectorXd& f, SparseMatrix& K) const {
  if (patches_) return addPatchForcesAndStiffness(x, &pattern, scale, f, &K);
  InvertedTets inverted;
  forEachRegion([&](const auto& material, const std::vector<int>& tets) {
    for (int t : tets) {
      const Eigen::Vector4i tet = T_.row(t);
      const auto& G = gradN_[t];
      const Mat3 F = deformationGradient(x, tet, G);
      inverted.check<std::decay_t<decltype(material)>>(t, F);
      ElementForces H;
      Mat12 Ke;
      elementForcesAndStiffness(material, F, G, volume_[t], H, Ke);
      for (int a = 0; a < 4; ++a) f.segment<3>(3 * tet(a)) += H.col(a);
      if (scale != 1.0) Ke *= scale;
      scatterTetBlock(pattern, t, Ke, K);
    }
  });
  inverted_ = inverted.count;
  inverted.throwIfAny();
}

// Calls visit(material, split, patches) once per region with the concrete material type, its
// VolumetricSplit and the region's patch indices (the constructor refused laws without a split).
template <class Visitor>
void TetElasticity::forEachPatchRegion(Visitor&& visit) const {
  for (size_t r = 0; r < materials_.size(); ++r)
    std::visit(
        [&](const auto& material) {
          using M = std::decay_t<decltype(material)>;
          if constexpr (hasVolumetricSplit<M>)
            visit(material, VolumetricSplit<M>{}, patchesOfRegion_[r]);
        },
        materials_[r]);
}

double TetElasticity::patchEnergy(const Eigen::VectorXd& x) const {
  double W = 0.0;
  forEachPatchRegion([&](const auto& material, auto split, const std::vector<int>& patches) {
    const auto dev = split.deviatoric(material);
    for (int p : patches) {
      double VP = 0.0, VTheta = 0.0;
      for (int t : patches_->tets[p]) {
        const Mat3 F = deformationGradient(x, T_.row(t), gradN_[t]);
        W += volume_[t] * dev.energy(F);
        VTheta += volume_[t] * split.theta(F);
        VP += volume_[t];
      }
      W += 0.5 * material.lambda * VTheta * VTheta / VP;
    }
  });
  return W;
}

// Per patch P with thetabar = sum_t V_t theta_t / V_P and g_t = V_t dtheta_t/dx:
// f = sum_t f_dev,t + lambda thetabar sum_t g_t,
// K = sum_t [K_dev,t + lambda thetabar V_t d2theta_t/dx2] + (lambda / V_P) (sum_t g_t)(sum_t
// g_t)^T.
void TetElasticity::addPatchForcesAndStiffness(const Eigen::VectorXd& x,
                                               const AssemblyPattern* pattern, double scale,
                                               Eigen::VectorXd& f, SparseMatrix* K) const {
  InvertedTets inverted;
  double* values = K ? K->valuePtr() : nullptr;
  std::vector<Mat3> Fs;
  Eigen::VectorXd gSum;
  forEachPatchRegion([&](const auto& material, auto split, const std::vector<int>& patches) {
    const auto dev = split.deviatoric(material);
    for (int p : patches) {
      const auto& tets = patches_->tets[p];
      const auto& local = patches_->local[p];
      const int m = static_cast<int>(patches_->nodes[p].size());
      Fs.resize(tets.size());
      double VP = 0.0, VTheta = 0.0;
      for (size_t k = 0; k < tets.size(); ++k) {
        const int t = tets[k];
        Fs[k] = deformationGradient(x, T_.row(t), gradN_[t]);
        inverted.check<std::decay_t<decltype(material)>>(t, Fs[k]);
        VTheta += volume_[t] * split.theta(Fs[k]);
        VP += volume_[t];
      }
      const double lambdaTheta = material.lambda * VTheta / VP;
      gSum.setZero(3 * m);
      for (size_t k = 0; k < tets.size(); ++k) {
        const int t = tets[k];
        const Eigen::Vector4i tet = T_.row(t);
        const auto& G = gradN_[t];
        const Eigen::Matrix<double, 3, 4> g = volume_[t] * split.dTheta(Fs[k]) * G.transpose();
        ElementForces H;
        if (K) {
          Mat12 Ke;
          elementForcesAndStiffness(dev, Fs[k], G, volume_[t], H, Ke);
          split.addHessian(Fs[k], G, lambdaTheta * volume_[t], Ke);
          if (scale != 1.0) Ke *= scale;
          scatterTetBlock(*pattern, t, Ke, *K);
        } else {
          H.noalias() = volume_[t] * dev.pk1(Fs[k]) * G.transpose();
        }
        H += lambdaTheta * g;
        for (int a = 0; a < 4; ++a) {
          f.segment<3>(3 * tet(a)) += H.col(a);
          gSum.segment<3>(3 * local[4 * k + a]) += g.col(a);
        }
      }
      if (K) {
        const double c = scale * material.lambda / VP;
        const int* slot = pattern->cliqueSlots(p);
        const int n = 3 * m;
        for (int i = 0; i < n; ++i) {
          const double ci = c * gSum(i);
          for (int j = 0; j < n; ++j) values[slot[n * i + j]] += ci * gSum(j);
        }
      }
    }
  });
  inverted_ = inverted.count;
  inverted.throwIfAny();
}

}  // namespace bcassim
