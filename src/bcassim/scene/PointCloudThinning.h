// A point-cloud observation's frames averaged down to its voxel_size and max_points
// (mesh/VoxelGrid), wherever the frames come from: files a scene names, or a pipeline's own camera.
#pragma once
#include <string>
#include <vector>

#include "bcassim/scene/AssimilationSettings.h"

namespace bcassim {

// Every present frame of pc on its voxel grid (pc.voxelSize, m) and under pc.maxPoints, on
// coarser grids until it has no more; frames already within both are left as they are. One
// notice, added to `notices`, says what it did (none where nothing was thinned).
void thinPointCloudFrames(PointCloudSettings& pc, std::vector<std::string>& notices);

}  // namespace bcassim
