#include "bcassim/scene/RegionReader.h"

#include "bcassim/io/IndexListReader.h"

namespace bcassim::yamlio {

namespace {

BoxRegion parseBox(const YamlSource& source, const YAML::Node& node, const std::string& path) {
  MapReader r(source, node, path, {"min", "max"});
  if (!r.has("min") || !r.has("max")) r.fail(r.has("min") ? "max" : "min", "missing (corner, m)");
  BoxRegion box{r.vec3("min", Vec3::Zero(), "m"), r.vec3("max", Vec3::Zero(), "m")};
  for (int i = 0; i < 3; ++i)
    if (box.min(i) > box.max(i))
      r.fail("max", "expected max >= min in every coordinate, but max[" + std::to_string(i) +
                        "] < min[" + std::to_string(i) + "]");
  return box;
}

SphereRegion parseSphere(const YamlSource& source, const YAML::Node& node,
                         const std::string& path) {
  MapReader r(source, node, path, {"center", "radius"});
  if (!r.has("center")) r.fail("center", "missing (centre, m)");
  if (!r.has("radius")) r.fail("radius", "missing (m)");
  return {r.vec3("center", Vec3::Zero(), "m"), r.number("radius", 0.0, "m", Range::NonNegative)};
}

}  // namespace

Region parseRegion(const YamlSource& source, const YAML::Node& node, const std::string& path) {
  MapReader r(source, node, path,
              {"box", "sphere", "half_space", "nodes", "nodes_file", "surface_patch"});
  int kinds = 0;
  for (const char* k : {"box", "sphere", "half_space", "nodes", "nodes_file", "surface_patch"})
    kinds += r.has(k) ? 1 : 0;
  if (kinds != 1)
    failAt(source, node, path,
           "expected exactly one of box, sphere, half_space, nodes, nodes_file, surface_patch, "
           "got " +
               (kinds == 0 ? std::string("none") : std::to_string(kinds)));
  if (r.has("box")) return parseBox(source, r.node("box"), r.pathOf("box"));
  if (r.has("sphere")) return parseSphere(source, r.node("sphere"), r.pathOf("sphere"));
  if (r.has("half_space")) {
    MapReader h(source, r.node("half_space"), r.pathOf("half_space"), {"point", "normal"});
    if (!h.has("normal")) h.fail("normal", "missing (direction pointing into the region)");
    const Vec3 normal = h.vec3("normal", Vec3::UnitZ(), "-");
    if (normal.norm() == 0) h.fail("normal", "must not be the zero vector");
    return HalfSpaceRegion{h.vec3("point", Vec3::Zero(), "m"), normal};
  }
  if (r.has("nodes")) {
    IndexListRegion list;
    const auto elements = listElements(source, r.node("nodes"), r.pathOf("nodes"));
    for (size_t i = 0; i < elements.size(); ++i)
      list.indices.push_back(
          parseInteger(source, elements[i], r.pathOf("nodes") + "[" + std::to_string(i) + "]"));
    return list;
  }
  if (r.has("nodes_file")) {
    const std::string file = r.existingFile("nodes_file");
    IndexListRegion list;
    withContext(source, r.node("nodes_file"), r.pathOf("nodes_file"),
                [&] { list.indices = readIndexList(file); });
    return list;
  }
  MapReader p(source, r.node("surface_patch"), r.pathOf("surface_patch"),
              {"box", "sphere", "direction", "max_angle_deg"});
  SurfacePatchRegion patch;
  if (p.has("box") == p.has("sphere"))
    failAt(source, p.self(), r.pathOf("surface_patch"),
           "expected exactly one of box, sphere (the part of the surface to take)");
  if (p.has("box"))
    patch.within = parseBox(source, p.node("box"), p.pathOf("box"));
  else
    patch.within = parseSphere(source, p.node("sphere"), p.pathOf("sphere"));
  if (p.has("direction")) {
    patch.direction = p.vec3("direction", Vec3::UnitZ(), "-");
    if (patch.direction->norm() == 0) p.fail("direction", "must not be the zero vector");
  }
  patch.maxAngleDeg = p.number("max_angle_deg", 90.0, "degrees", Range::NonNegative);
  p.rejectUnless(p.has("direction"), "max_angle_deg", "a surface_patch with a direction");
  return patch;
}

std::vector<int> selectRegionNodes(const YamlSource& source, const YAML::Node& node,
                                   const std::string& path, const TetMesh& mesh) {
  const Region region = parseRegion(source, node, path);
  std::vector<int> nodes;
  withContext(source, node, path, [&] { nodes = selectNodes(mesh, region); });
  if (nodes.empty()) failAt(source, node, path, "selects no node of the mesh");
  return nodes;
}

}  // namespace bcassim::yamlio
