// Reading a YAML scene file (format in docs/scene-format.md) into a Scene: mesh, materials,
// boundary conditions, loads, ligament springs, control points, markers, output and variants.
#pragma once
#include <string>

#include "bcassim/scene/Scene.h"

namespace bcassim {

// Limits on the work a scene may ask for before anything is built; a scene's own keys (e.g.
// mesh.max_nodes) override them.
struct SceneLimits {
  // Default of mesh.max_nodes: a generated mesh beyond it is refused (a few hundred MB of mesh).
  int maxGeneratedNodes = 2000000;
};

// Loads `path`; relative paths inside the scene resolve against its directory. Throws InputError
// with one line "<path>:<line>: <key path>: <what was expected>", e.g.
// "scene.yaml:7: time.dt: expected a number in seconds, got 'fast'"; files the scene refers to
// that are malformed give "<path>:<line>: mesh.file: <the reader's message>".
Scene loadScene(const std::string& path, const SceneLimits& limits = {});

// Same from YAML text; `sourceName` stands for the file in messages and `directory` is where
// relative paths resolve.
Scene loadSceneFromString(const std::string& yaml, const std::string& sourceName,
                          const std::string& directory, const SceneLimits& limits = {});

}  // namespace bcassim
