// Scene regions in YAML (box, sphere, half_space, nodes, surface_patch) turned into mesh/Region.h
// selections, with the scene file position in every error.
#pragma once
#include <yaml-cpp/yaml.h>

#include <string>
#include <vector>

#include "bcassim/mesh/Region.h"
#include "bcassim/mesh/TetMesh.h"
#include "bcassim/scene/YamlReader.h"

namespace bcassim::yamlio {

// Parses a region map with exactly one of the keys box, sphere, half_space, nodes, surface_patch.
Region parseRegion(const YamlSource& source, const YAML::Node& node, const std::string& path);

// Parses and selects the region's nodes; fails "<path>: selects no node of the mesh" when empty.
std::vector<int> selectRegionNodes(const YamlSource& source, const YAML::Node& node,
                                   const std::string& path, const TetMesh& mesh);

}  // namespace bcassim::yamlio
