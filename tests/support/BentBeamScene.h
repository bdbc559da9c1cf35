// A beam bent by a tip load, as a scene text for tests: 20 nodes (4 x 1 x 1 cells of a 0.1 m
// box), the root fixed, 2 mN at the tip, 2 markers, 6 steps of 0.05 s; and that box pulled hard.
#pragma once
#include <fmt/format.h>

#include <string>

namespace bcassim::test {

// `output` is the output: section's contents, e.g. "pvd: false, every: 2".
inline std::string bentBeamScene(double youngModulus, const std::string& output = "pvd: false") {
  return fmt::format(
      "mesh: {{generator: box, size: [0.1, 0.02, 0.02], cells: [4, 1, 1]}}\n"
      "material: {{model: stvk, young_modulus: {}, poisson_ratio: 0.3}}\n"
      "fixed:\n  - region: {{box: {{min: [-1, -1, -1], max: [0.0001, 1, 1]}}}}\n"
      "loads:\n  - region: {{box: {{min: [0.0999, -1, -1], max: [1, 1, 1]}}}}\n"
      "    total_force: [0, 0, 0.002]\n"
      "markers:\n  - points: [[0.1, 0.01, 0.01], [0.05, 0.01, 0.01]]\n"
      "time: {{dt: 0.05, steps: 6}}\n"
      "output: {{{}}}\n",
      youngModulus, output);
}

// The same box pulled down at its tip by 10 N with its default material (8,000 Pa), 3 steps of
// 0.01 s that may not be cut (time.min_dt = dt): a sigma point near 500 Pa inverts an element,
// one at 2,250 Pa or more does not (the forecast retries' tests).
inline std::string pulledCantileverScene() {
  return "mesh: {generator: box, size: [0.1, 0.02, 0.02], cells: [4, 1, 1]}\n"
         "fixed: [{region: {box: {min: [-1, -1, -1], max: [0.001, 1, 1]}}}]\n"
         "loads: [{region: {box: {min: [0.099, -1, -1], max: [1, 1, 1]}}, "
         "total_force: [0, -10, 0]}]\n"
         "markers:\n  - points: [[0.1, 0.01, 0.01], [0.05, 0.01, 0.01]]\n"
         "time: {dt: 0.01, steps: 3, min_dt: 0.01}\n"
         "output: {pvd: false}\n";
}

}  // namespace bcassim::test
