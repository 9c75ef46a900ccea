// The straight-line shell element (see the header): the bench's reference for the stage framework.
#include "tools/bench/straight_line_shell.h"

#include <algorithm>
#include <stdexcept>
#include <string>

namespace jetshell {
namespace {

/// The edge vectors (e0, e1) = (x1 − x0, x2 − x0) of face f.
void edgeVectors(const double* x, const Faces& F, int f, Eigen::Vector3d& e0, Eigen::Vector3d& e1) {
  const Eigen::Map<const Eigen::Vector3d> x0(x + 3 * F(f, 0)), x1(x + 3 * F(f, 1)), x2(x + 3 * F(f, 2));
  e0 = x1 - x0;
  e1 = x2 - x0;
}

}  // namespace

StraightLineShell::StraightLineShell(const TriMesh& mesh, const Topology& topology, const ShellReference& reference,
                                     double lambda, double mu, double alpha, double beta,
                                     const StencilTable& bendingStencils)
    : ref_(reference), F_(mesh.F), topo_(topology) {
  const int nf = mesh.numFaces(), ne = topo_.numEdges();
  if (bendingStencils.width != 6 || bendingStencils.size() != nf)
    throw std::invalid_argument("straight-line shell: the bending stencils must be 6 vertices per face");
  stencil_.resize(static_cast<std::size_t>(nf));
  for (int f = 0; f < nf; ++f) {
    const int* ids = bendingStencils.element(f);
    for (int k = 0; k < 6; ++k) stencil_[static_cast<std::size_t>(f)][static_cast<std::size_t>(k)] = ids[k];
    for (int k = 0; k < 3; ++k)
      if (ids[k] != F_(f, k))
        throw std::invalid_argument("straight-line shell: stencil " + std::to_string(f) + " does not start with its face");
  }
  meanRows_.resize(static_cast<std::size_t>(nf));
  for (int f = 0; f < nf; ++f)
    for (int i = 0; i < 3; ++i) {
      const int e = topo_.faceEdges(f, i);
      for (int side = 0; side < 2; ++side) {
        const int g = topo_.edgeFaces(e, side);
        for (int k = 0; k < 3; ++k) {
          int row = -1;
          if (g >= 0) {
            const auto& s = stencil_[static_cast<std::size_t>(f)];
            const auto it = std::find(s.begin(), s.end(), F_(g, k));
            if (it == s.end())
              throw std::invalid_argument("straight-line shell: stencil " + std::to_string(f) + " misses a vertex of face " +
                                          std::to_string(g));
            row = static_cast<int>(it - s.begin()) - 1;
          }
          meanRows_[static_cast<std::size_t>(f)][static_cast<std::size_t>(6 * i + 3 * side + k)] = static_cast<std::int8_t>(row);
        }
      }
    }
  // The second form's declared Hessians: no edge–edge or normal–normal curvature, and each edge–normal block a
  // multiple of the identity (checked, so that the element's strip form below is this stage's curvature).
  const auto& form = constantStageHessians<SecondFormStage>().hessians;
  for (int k = 0; k < 3; ++k) {
    const Eigen::Matrix<double, 15, 15>& h = form[static_cast<std::size_t>(k)];
    if (!h.topLeftCorner<6, 6>().isZero(0.0) || !h.bottomRightCorner<9, 9>().isZero(0.0))
      throw std::logic_error("straight-line shell: the second form is not bilinear in edges and normals");
    for (int a = 0; a < 2; ++a)
      for (int c = 0; c < 3; ++c) {
        const Mat3 block = h.block<3, 3>(3 * a, 6 + 3 * c);
        const double s = block(0, 0);
        if (!(block - s * Mat3::Identity()).isZero(0.0))
          throw std::logic_error("straight-line shell: a second-form block is not a multiple of the identity");
        formCoef_[static_cast<std::size_t>(k)][static_cast<std::size_t>(a)][static_cast<std::size_t>(c)] = s;
      }
  }
  for (int k = 0; k < 3; ++k)
    metricHessians_[static_cast<std::size_t>(k)] = constantStageHessians<MetricStage>().hessians[static_cast<std::size_t>(k)];
  bendingStage_.ref = &ref_;
  bendingStage_.alpha = alpha;
  bendingStage_.beta = beta;
  membraneStage_.ref = &ref_;
  membraneStage_.lambda = lambda;
  membraneStage_.mu = mu;
  normal_.resize(static_cast<std::size_t>(nf));
  normalAdjoint_.resize(static_cast<std::size_t>(nf));
  normalJacobian_.resize(static_cast<std::size_t>(nf));
  mean_.resize(static_cast<std::size_t>(ne));
  midEdge_.resize(static_cast<std::size_t>(ne));
  midEdgeAdjoint_.resize(static_cast<std::size_t>(ne));
  kelvinJacobian_.resize(static_cast<std::size_t>(ne));
}

double StraightLineShell::evaluate(const Eigen::VectorXd& x, DerivativePath path, Eigen::VectorXd* g,
                                   HessianAssembler* hessian, int slot) {
  const int order = hessian != nullptr ? 2 : g != nullptr ? 1 : 0;
  double* gradient = g != nullptr ? g->data() : nullptr;
  faces(x.data(), path, order);
  edges(path, order);
  double energy = secondForms(x.data(), path, order, hessian == nullptr, gradient);
  if (order == 0) return energy;
  edgeAdjoints();
  energy += elements(x.data(), path, gradient, hessian, slot);
  return energy;
}

void StraightLineShell::faces(const double* x, DerivativePath path, int order) {
  const int nf = static_cast<int>(F_.rows());
  for (int f = 0; f < nf; ++f) {
    const auto k = static_cast<std::size_t>(f);
    Vec3 e0, e1;
    edgeVectors(x, F_, f, e0, e1);
    const double z[6] = {e0[0], e0[1], e0[2], e1[0], e1[1], e1[2]};
    StageDerivativesOf<FaceNormalStage> d;
    evaluateStage(faceStage_, z, f, std::min(order, 1), path, d);
    normal_[k] = d.value;
    if (order < 1) continue;
    normalJacobian_[k] = d.jacobian;
    normalAdjoint_[k].setZero();
  }
}

void StraightLineShell::edges(DerivativePath path, int order) {
  const int ne = topo_.numEdges();
  for (int e = 0; e < ne; ++e) {
    const auto k = static_cast<std::size_t>(e);
    const int A = topo_.edgeFaces(e, 0), B = topo_.edgeFaces(e, 1);
    // The page's free rule on a boundary edge: the missing normal is the face's own.
    const Vec3 m = B >= 0 ? Vec3(0.5 * (normal_[static_cast<std::size_t>(A)] + normal_[static_cast<std::size_t>(B)]))
                          : normal_[static_cast<std::size_t>(A)];
    mean_[k] = m;
    StageDerivativesOf<KelvinStage> d;
    evaluateStage(kelvinStage_, m.data(), e, std::min(order, 1), path, d);
    midEdge_[k] = d.value;
    if (order < 1) continue;
    kelvinJacobian_[k] = d.jacobian;
    midEdgeAdjoint_[k].setZero();
  }
}

void StraightLineShell::addLeaves(int f, const double* ge, double* g) const {
  const int v0 = F_(f, 0), v1 = F_(f, 1), v2 = F_(f, 2);
  for (int c = 0; c < 3; ++c) {
    g[3 * v1 + c] += ge[c];
    g[3 * v2 + c] += ge[3 + c];
    g[3 * v0 + c] -= ge[c] + ge[3 + c];
  }
}

double StraightLineShell::membrane(int f, const Vec3& e0, const Vec3& e1, DerivativePath path, int order,
                                   Eigen::Matrix<double, 6, 1>& ge, Eigen::Matrix<double, 6, 6>* h) const {
  const double z[6] = {e0[0], e0[1], e0[2], e1[0], e1[1], e1[2]};
  StageDerivativesOf<MetricStage> da;
  evaluateStage(metricStage_, z, f, std::min(order, 1), path, da);
  StageDerivativesOf<MembraneDensityStage> dw;
  evaluateStage(membraneStage_, da.value.data(), f, h != nullptr ? 2 : std::min(order, 1), path, dw);
  if (order < 1) return dw.value[0];
  const Vec3 ga = dw.jacobian.transpose();
  ge.noalias() = da.jacobian.transpose() * ga;
  if (h != nullptr) {
    const Eigen::Matrix<double, 3, 6> HJ = dw.hessians[0] * da.jacobian;
    h->noalias() = da.jacobian.transpose() * HJ;
    for (int k = 0; k < 3; ++k) h->noalias() += ga[k] * metricHessians_[static_cast<std::size_t>(k)];
  }
  return dw.value[0];
}

double StraightLineShell::secondForms(const double* x, DerivativePath path, int order, bool withMembrane, double* g) {
  const int nf = static_cast<int>(F_.rows());
  double energy = 0.0;
  for (int f = 0; f < nf; ++f) {
    Vec3 e0, e1;
    edgeVectors(x, F_, f, e0, e1);
    double z[15];
    for (int c = 0; c < 3; ++c) {
      z[c] = e0[c];
      z[3 + c] = e1[c];
      for (int i = 0; i < 3; ++i) z[6 + 3 * i + c] = midEdge_[static_cast<std::size_t>(topo_.faceEdges(f, i))][c];
    }
    StageDerivativesOf<SecondFormStage> db;
    evaluateStage(formStage_, z, f, std::min(order, 1), path, db);
    StageDerivativesOf<BendingDensityStage> dw;
    evaluateStage(bendingStage_, db.value.data(), f, std::min(order, 1), path, dw);
    energy += dw.value[0];
    Eigen::Matrix<double, 6, 1> ge;
    if (withMembrane) {
      energy += membrane(f, e0, e1, path, order, ge, nullptr);
      if (order >= 1 && g != nullptr) addLeaves(f, ge.data(), g);
    }
    if (order < 1) continue;
    const Eigen::Matrix<double, 15, 1> zbar = db.jacobian.transpose() * dw.jacobian.transpose();
    for (int i = 0; i < 3; ++i)
      midEdgeAdjoint_[static_cast<std::size_t>(topo_.faceEdges(f, i))] += zbar.segment<3>(6 + 3 * i);
    if (g != nullptr) addLeaves(f, zbar.data(), g);
  }
  return energy;
}

void StraightLineShell::edgeAdjoints() {
  const int ne = topo_.numEdges();
  for (int e = 0; e < ne; ++e) {
    const auto k = static_cast<std::size_t>(e);
    const Vec3 v = kelvinJacobian_[k].transpose() * midEdgeAdjoint_[k];
    const int A = topo_.edgeFaces(e, 0), B = topo_.edgeFaces(e, 1);
    if (B < 0) {
      normalAdjoint_[static_cast<std::size_t>(A)] += v;
    } else {
      normalAdjoint_[static_cast<std::size_t>(A)] += 0.5 * v;
      normalAdjoint_[static_cast<std::size_t>(B)] += 0.5 * v;
    }
  }
}

void StraightLineShell::meanTotal(int f, int i, Totals& t) const {
  t.setZero();
  const int e = topo_.faceEdges(f, i);
  const bool boundary = topo_.edgeFaces(e, 1) < 0;
  const double w = boundary ? 1.0 : 0.5;
  for (int side = 0; side < (boundary ? 1 : 2); ++side) {
    const Jacobian36& J = normalJacobian_[static_cast<std::size_t>(topo_.edgeFaces(e, side))];
    const std::int8_t* rows = meanRows_[static_cast<std::size_t>(f)].data() + 6 * i + 3 * side;
    // n over the face's vertices (g0, g1, g2): −(J0 + J1), J0, J1.
    if (rows[1] >= 0) t.middleRows<3>(3 * rows[1]) += w * J.leftCols<3>().transpose();
    if (rows[2] >= 0) t.middleRows<3>(3 * rows[2]) += w * J.rightCols<3>().transpose();
    if (rows[0] >= 0) t.middleRows<3>(3 * rows[0]) -= w * (J.leftCols<3>() + J.rightCols<3>()).transpose();
  }
}

double StraightLineShell::elements(const double* x, DerivativePath path, double* g, HessianAssembler* hessian,
                                   int slot) {
  // Products over the 16 rows are written lazy: Eigen would send a 16×3 by 3×16 product to its blocked GEMM
  // (measured: a fifth of the element's time in packing and kernels).
  const int nf = static_cast<int>(F_.rows());
  double energy = 0.0;
  for (int f = 0; f < nf; ++f) {
    const auto fk = static_cast<std::size_t>(f);
    const Eigen::Matrix<double, 6, 1> gn = normalJacobian_[fk].transpose() * normalAdjoint_[fk];
    if (g != nullptr) addLeaves(f, gn.data(), g);
    if (hessian == nullptr) continue;
    Vec3 e0, e1;
    edgeVectors(x, F_, f, e0, e1);
    int edge[3];
    Totals meanT[3], kelvinT[3];
    double z[15];
    for (int i = 0; i < 3; ++i) {
      edge[i] = topo_.faceEdges(f, i);
      const auto ek = static_cast<std::size_t>(edge[i]);
      meanTotal(f, i, meanT[i]);
      kelvinT[i].noalias() = meanT[i].lazyProduct(kelvinJacobian_[ek].transpose());
      for (int c = 0; c < 3; ++c) z[6 + 3 * i + c] = midEdge_[ek][c];
    }
    for (int c = 0; c < 3; ++c) {
      z[c] = e0[c];
      z[3 + c] = e1[c];
    }
    StageDerivativesOf<SecondFormStage> db;
    evaluateStage(formStage_, z, f, 1, path, db);
    StageDerivativesOf<BendingDensityStage> dw;
    evaluateStage(bendingStage_, db.value.data(), f, 2, path, dw);
    const Vec3 gb = dw.jacobian.transpose();
    // b's total (transposed): the edge vectors are the working rows 0–2 and 3–5; the normals through their totals.
    Totals formT;
    formT.noalias() = kelvinT[0].lazyProduct(db.jacobian.middleCols<3>(6).transpose());
    formT.noalias() += kelvinT[1].lazyProduct(db.jacobian.middleCols<3>(9).transpose());
    formT.noalias() += kelvinT[2].lazyProduct(db.jacobian.middleCols<3>(12).transpose());
    formT.topRows<3>() += db.jacobian.leftCols<3>().transpose();
    formT.middleRows<3>(3) += db.jacobian.middleCols<3>(3).transpose();
    Work H;
    const Totals HT = formT.lazyProduct(dw.hessians[0]);
    H.noalias() = HT.lazyProduct(formT.transpose());
    // The second form's curvature Σ_k g_k ∇²b_k: edge vector a against normal c, a multiple of the identity.
    for (int a = 0; a < 2; ++a) {
      Totals strip = Totals::Zero();
      for (int c = 0; c < 3; ++c) {
        double s = 0.0;
        for (int k = 0; k < 3; ++k)
          s += gb[k] * formCoef_[static_cast<std::size_t>(k)][static_cast<std::size_t>(a)][static_cast<std::size_t>(c)];
        if (s != 0.0) strip += s * kelvinT[c];
      }
      H.middleCols<3>(3 * a) += strip;
      H.middleRows<3>(3 * a) += strip.transpose();
    }
    // The Kelvin curvature of the edges this face owns, with the edge's whole adjoint.
    for (int i = 0; i < 3; ++i) {
      const auto ek = static_cast<std::size_t>(edge[i]);
      if (topo_.edgeFaces(edge[i], 0) != f) continue;
      Mat3 C;
      weightedStageHessian(kelvinStage_, mean_[ek].data(), edge[i], path, midEdgeAdjoint_[ek].data(), C);
      const Totals CM = meanT[i].lazyProduct(C);
      H.noalias() += CM.lazyProduct(meanT[i].transpose());
    }
    // The face normal's own curvature (its leaves are the working rows 0–5) and the membrane's.
    const double zn[6] = {e0[0], e0[1], e0[2], e1[0], e1[1], e1[2]};
    Eigen::Matrix<double, 6, 6> C6;
    weightedStageHessian(faceStage_, zn, f, path, normalAdjoint_[fk].data(), C6);
    H.topLeftCorner<6, 6>() += C6;
    Eigen::Matrix<double, 6, 1> ge;
    energy += membrane(f, e0, e1, path, 2, ge, &C6);
    H.topLeftCorner<6, 6>() += C6;
    if (g != nullptr) addLeaves(f, ge.data(), g);
    // The base vertex's row and column (a common translation changes nothing); only the upper triangle is read.
    Eigen::Matrix<double, 18, 18> block;
    block.bottomRightCorner<15, 15>() = H.topLeftCorner<15, 15>();
    Eigen::Matrix<double, 15, 3> rowSums = -H.block<15, 3>(0, 0);
    for (int c = 1; c < 5; ++c) rowSums -= H.block<15, 3>(0, 3 * c);
    block.block<3, 15>(0, 3) = rowSums.transpose();
    Mat3 base = -rowSums.topRows<3>();
    for (int r = 1; r < 5; ++r) base -= rowSums.middleRows<3>(3 * r);
    block.topLeftCorner<3, 3>() = base;
    hessian->addElementHessian(slot, f, block.data());
  }
  return energy;
}

}  // namespace jetshell
