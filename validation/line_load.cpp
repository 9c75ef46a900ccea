#include "validation/line_load.h"

#include <string>

namespace jetshell::validation {
namespace {

void checkChain(const TriMesh& mesh, const std::vector<int>& chain, const char* what) {
  if (chain.size() < 2) throw InputError(std::string(what) + ": the chain needs at least two vertices");
  for (std::size_t k = 0; k < chain.size(); ++k)
    if (chain[k] < 0 || chain[k] >= mesh.numVertices())
      throw InputError(std::string(what) + ": chain vertex " + std::to_string(k) + " = " +
                       std::to_string(chain[k]) + " is out of range [0, " + std::to_string(mesh.numVertices()) +
                       ")");
}

}  // namespace

double chainLength(const TriMesh& mesh, const std::vector<int>& chain) {
  checkChain(mesh, chain, "chain length");
  double length = 0.0;
  for (std::size_t k = 0; k + 1 < chain.size(); ++k)
    length += (mesh.V.row(chain[k + 1]) - mesh.V.row(chain[k])).norm();
  return length;
}

Eigen::VectorXd consistentLineLoad(const TriMesh& mesh, const std::vector<int>& chain,
                                   const Eigen::Vector3d& forcePerLength) {
  checkChain(mesh, chain, "line load");
  Eigen::VectorXd f = Eigen::VectorXd::Zero(3 * mesh.numVertices());
  for (std::size_t k = 0; k + 1 < chain.size(); ++k) {
    const double half = 0.5 * (mesh.V.row(chain[k + 1]) - mesh.V.row(chain[k])).norm();
    f.segment<3>(3 * chain[k]) += half * forcePerLength;
    f.segment<3>(3 * chain[k + 1]) += half * forcePerLength;
  }
  return f;
}

}  // namespace jetshell::validation
