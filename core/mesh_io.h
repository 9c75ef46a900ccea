// Wavefront OBJ input and output of triangle meshes.
//
// Reading keeps `v` and `f` statements (faces with more than three corners are fan-triangulated; `v/vt/vn`
// corners and negative, relative indices are accepted) and skips the rest (vt, vn, g, o, s, usemtl, mtllib, #).
// Every problem is an InputError that names the file and line: a malformed number, an index out of range, a
// repeated corner, a degenerate face, a non-finite coordinate, an edge shared by three or more faces, or two
// neighbouring faces with opposite orientation.
#pragma once

#include "core/mesh.h"

#include <iosfwd>
#include <string>
#include <vector>

namespace jetshell {

/// A mesh read from OBJ text, with the source line of every vertex and triangle (for error messages).
struct ObjMesh {
  TriMesh mesh;
  std::vector<int> vertexLine;  // size N
  std::vector<int> faceLine;    // size F (a fan-triangulated polygon gives several faces the same line)
};

/// Parses OBJ text; `name` is the file name used in messages ("name:line: ..."). Validates as described above.
ObjMesh parseObj(std::istream& in, const std::string& name);

/// Reads an OBJ file. Throws InputError "path: cannot open" when the file is missing or unreadable.
TriMesh readObj(const std::string& path);

/// Writes `v` and `f` statements (1-based indices) with full double precision: positions V (N×3, e.g. a
/// deformed configuration) and faces F. Atomic file writing is the caller's concern (tools/output).
void writeObj(std::ostream& out, const Positions& V, const Faces& F);

}  // namespace jetshell
