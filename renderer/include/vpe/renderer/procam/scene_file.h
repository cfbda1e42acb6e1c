// SPDX-License-Identifier: MIT
// Scene files: a simulated installation as TOML (renderer/procam/README.md, "Scene files") —
// what `vpe synth-procam` writes, what a technician edits to rehearse an installation and what
// vpe-player's simulated camera reads. The object's mesh is a Wavefront OBJ beside it.
#pragma once

#include <filesystem>
#include <string>

#include "vpe/proto/input_error.h"
#include "vpe/renderer/procam/procam_scene.h"

namespace vpe::renderer::procam {

struct SceneFile {
    ProcamScene scene;
    SimulatedCamera camera;
    std::filesystem::path meshPath;  // the object's OBJ, as resolved (empty without an object)
};

// One line: "file:section.key: problem" or "file: problem".
class SceneFileError : public proto::InputError {
public:
    using proto::InputError::InputError;
};

// Reads and checks the file and the object's OBJ (tinyobjloader; triangulated; every vertex
// with a normal and a texture coordinate). Unknown keys, wrong types and values out of range
// are refused with SceneFileError naming the key.
SceneFile readSceneFile(const std::filesystem::path& path);

// Writes the scene and camera as TOML, atomically, naming `objectMesh` (a path relative to the
// file's folder, written by the caller) for the object. Throws SceneFileError when it cannot.
void writeSceneFile(const std::filesystem::path& path, const ProcamScene& scene,
                    const SimulatedCamera& camera, const std::string& objectMesh);

// Reads an OBJ as a ScreenObject at the identity pose (SceneFileError naming the file).
ScreenObject readObjectMesh(const std::filesystem::path& path);

}  // namespace vpe::renderer::procam
