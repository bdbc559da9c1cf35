// Varifold (eq. 4.5) and current inner products <A, B> = sum_ij exp(-|c_i - d_j|^2 / sigma^2)
// g(n_i, m_j), g = (n.m)^2 / (|n||m|) (varifold, orientation-blind) or g = n.m (current).
#pragma once
#include <Eigen/Core>

#include "bcassim/atlas/OrientedFaces.h"

namespace bcassim {

enum class FaceKernelKind { Varifold, Current };

// Returns <a, b>. When gc and gn are non-null they receive d<a, b>/dc_i and d<a, b>/dn_i
// (#a by 3 each, resized) with b held fixed. sigma: kernel width (m).
// Blocked over (i, j) tiles, vectorised over j (AVX-512, AVX2+FMA or SSE, picked at run time),
// parallel over blocks of i; deterministic on a given CPU.
double faceKernelSum(const OrientedFaces& a, const OrientedFaces& b, double sigma,
                     FaceKernelKind kind, Eigen::MatrixX3d* gc = nullptr,
                     Eigen::MatrixX3d* gn = nullptr);

}  // namespace bcassim
