// Reading a YAML scene file (format in docs/scene-format.md) into a Scene: mesh, materials,
// boundary conditions, loads, ligament springs, control points, markers, output and variants.
#pragma once
#include <string>

#include "bcassim/scene/Scene.h"

namespace bcassim {

// Loads `path`; relative paths inside the scene resolve against its directory. Throws InputError
// with one line "<path>:<line>: <key path>: <what was expected>", e.g.
// "scene.yaml:7: time.dt: expected a number in seconds, got 'fast'"; files the scene refers to
// that are malformed give "<path>:<line>: mesh.file: <the reader's message>".
Scene loadScene(const std::string& path);

// Same from YAML text; `sourceName` stands for the file in messages and `directory` is where
// relative paths resolve.
Scene loadSceneFromString(const std::string& yaml, const std::string& sourceName,
                          const std::string& directory);

}  // namespace bcassim
