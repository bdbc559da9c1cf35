// The thesis cylinder made small, as a scene text for tests: a periodic pull at mid-length,
// markers on the front, every node a validation point; the caller adds fixed ends and the rest.
#pragma once
#include <string>

namespace bcassim::test {

// `material` holds the material: and solver: lines, `output` the output: line.
inline std::string pulledCylinderScene(int nodes, const std::string& material, int steps,
                                       int markers, const std::string& output) {
  return "mesh: {generator: cylinder, radius: 0.015, length: 0.18, target_nodes: " +
         std::to_string(nodes) + "}\n" + material +
         "damping: {rayleigh_mass: 0.1, rayleigh_stiffness: 0.01}\n"
         "time: {dt: 0.01, steps: " +
         std::to_string(steps) + "}\n" + output +
         "loads:\n"
         "  - region: {surface_patch: {box: {min: [-0.02, -0.02, 0.075], max: [0.02, 0.02, "
         "0.105]}, direction: [0, -1, 0], max_angle_deg: 60}}\n"
         "    total_force: [0, -0.15, 0]\n"
         "    profile: {kind: sine, period: 1.0}\n"
         "markers:\n"
         "  - region: {surface_patch: {box: {min: [-0.02, -0.02, 0.03], max: [0.02, 0.02, "
         "0.15]}, direction: [0, 1, 0], max_angle_deg: 60}}\n"
         "    count: " +
         std::to_string(markers) +
         "\n"
         "validation_points: {nodes: all}\n";
}

}  // namespace bcassim::test
