#include "bcassim/scene/PointCloudThinning.h"

#include <fmt/format.h>

#include <algorithm>

#include "bcassim/mesh/VoxelGrid.h"

namespace bcassim {

void thinPointCloudFrames(PointCloudSettings& pc, std::vector<std::string>& notices) {
  long long thinned = 0, before = 0, after = 0;
  double finest = 0.0, coarsest = 0.0;
  for (size_t k = 0; k < pc.frames.size(); ++k) {
    if (!pc.present[k] || pc.frames[k].rows() == 0) continue;
    const Eigen::Index n = pc.frames[k].rows();
    ThinnedPoints t = thinToAtMost(pc.frames[k], pc.maxPoints, pc.voxelSize);
    if (t.voxel == 0.0) continue;
    finest = thinned == 0 ? t.voxel : std::min(finest, t.voxel);
    coarsest = std::max(coarsest, t.voxel);
    ++thinned;
    before += n;
    after += t.points.rows();
    pc.frames[k] = std::move(t.points);
  }
  if (thinned == 0) return;
  notices.push_back(fmt::format(
      "point_cloud: {} frame{} averaged on voxel grids of {:.3g}{} mm (voxel_size {:.6g} m, "
      "max_points {}): {} points a frame on average, from {}",
      thinned, thinned == 1 ? "" : "s", 1e3 * finest,
      coarsest > finest ? fmt::format("-{:.3g}", 1e3 * coarsest) : std::string(), pc.voxelSize,
      pc.maxPoints, after / thinned, before / thinned));
}

}  // namespace bcassim
