// An energy term that is a stage graph (core/stage_graph.h) and nothing else: its elements are the graph's, its
// derivatives the evaluator's (core/stage_graph_evaluator.h). A user term declares its stages and layers, fills
// the graph's inputs, and hands the finalized graph to this class.
#pragma once

#include "core/fixed_stencil_term.h"
#include "core/stage_graph.h"
#include "core/stage_graph_evaluator.h"

#include <memory>
#include <string>
#include <utility>

namespace jetshell {

template <typename Graph>
class StageGraphTerm : public FixedStencilTerm {
 public:
  /// `graph` must be finalized. zeroAtRest / rigidInvariant: the conformance suite's expectations.
  StageGraphTerm(std::string name, Graph graph, bool zeroAtRest = true, bool rigidInvariant = true)
      : FixedStencilTerm(std::move(name), graph.elements(), graph.numVertices(), zeroAtRest, rigidInvariant),
        graph_(std::make_unique<Graph>(std::move(graph))),
        evaluator_(*graph_) {
    if (!graph_->finalized()) throw std::logic_error(name_ + ": the stage graph is not finalized");
  }

  /// A projection that knows the term's element blocks (StageGraphEvaluator::setElementProjector).
  void setElementProjector(typename StageGraphEvaluator<Graph>::ElementProjector projector) {
    evaluator_.setElementProjector(std::move(projector));
  }

  Graph& graph() { return *graph_; }
  const Graph& graph() const { return *graph_; }

  double evaluate(const Eigen::VectorXd& x, const EvalRequest& request, const EvalOptions& options) override {
    return evaluator_.evaluate(x, request, options, schedule_, elementEnergy_);
  }

 private:
  std::unique_ptr<Graph> graph_;  // on the heap: the evaluator keeps a reference to it
  StageGraphEvaluator<Graph> evaluator_;
};

}  // namespace jetshell
