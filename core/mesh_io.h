// Wavefront OBJ input and output of triangle meshes.
//
// Reading keeps `v` and `f` statements (faces with more than three corners are fan-triangulated; `v/vt/vn`
// corners and negative, relative indices are accepted; vertex colours `v x y z r g b` and a `w` are read and
// ignored) and skips the rest (vt, vn, g, o, s, usemtl, mtllib, #, unknown statements). CRLF line ends and a
// UTF-8 byte-order mark are accepted. Every problem is an InputError that names the file and line: a malformed
// number, an index that is 0 or out of range, binary data, a line longer than inputLimits().maxObjLineBytes, a
// file larger than maxObjBytes or with more than maxVertices / maxFaces, and every mesh defect validateMesh
// finds (repeated corner, degenerate face, duplicate or reversed-duplicate face, non-manifold edge, neighbours
// with opposite orientation, neighbours folded flat onto each other), with the other face named by its line.
// readObj reads only regular files (a FIFO or /dev/zero given as the mesh is an error, not a hang).
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

/// Reads an OBJ file. Throws InputError "path: cannot open mesh file" when it is missing or unreadable, and
/// names the path when it is not a regular file or too large (core/input_file.h).
TriMesh readObj(const std::string& path);

/// Writes `v` and `f` statements (1-based indices) with full double precision: positions V (N×3, e.g. a
/// deformed configuration) and faces F. Atomic file writing is the caller's concern (tools/output).
void writeObj(std::ostream& out, const Positions& V, const Faces& F);

}  // namespace jetshell
