// The JSON scene format (documented in SCENES.md): reads a file into a Scene, checking every field.
#pragma once

#include "tools/scene/scene.h"

#include <nlohmann/json.hpp>

#include <string>

namespace jetshell {

/// Reads and validates a scene file. Mesh paths are relative to the file's directory. Throws InputError with a
/// one-line message naming the JSON pointer of the field (or file:line for JSON syntax and OBJ errors).
Scene loadSceneFile(const std::string& path);
/// The same from a scene file's text, read once by the caller (which may also fingerprint or keep it): `path`
/// names the file in messages and its directory resolves relative mesh paths.
Scene sceneFromText(const std::string& text, const std::string& path);

/// The same from parsed JSON; baseDirectory resolves relative mesh paths.
Scene sceneFromJson(const nlohmann::json& document, const std::string& baseDirectory);

}  // namespace jetshell
