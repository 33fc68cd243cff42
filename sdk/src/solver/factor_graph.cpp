#include "plugslam/solver/factor_graph.h"

namespace plugslam {
inline namespace abi_v1 {

void FactorGraph::insertVariable(std::unique_ptr<Variable> v) {
  if (index_.count(v->id())) {
    throw InputError("duplicate variable id " + std::to_string(v->id()));
  }
  index_.emplace(v->id(), v.get());
  order_.push_back(v.get());
  owned_.push_back(std::move(v));
}

void FactorGraph::insertFactor(std::unique_ptr<FactorBase> f) {
  if (!f) throw InputError("null factor");
  const int m = f->numVariables();
  for (int i = 0; i < m; ++i) {
    Variable* v = f->variable(i);
    if (!v || findVariable(v->id()) != v) {
      throw InputError("factor refers to a variable that is not in this graph");
    }
    for (int j = 0; j < i; ++j) {
      if (f->variable(j) == v) {
        throw InputError("factor uses variable " + std::to_string(v->id()) + " twice");
      }
    }
  }
  factors_.push_back(std::move(f));
}

void FactorGraph::clear() {
  factors_.clear();
  index_.clear();
  order_.clear();
  owned_.clear();
}

double FactorGraph::robustChi2() const {
  double s = 0.0;
  for (const auto& f : factors_) s += f->robustChi2();
  return s;
}

double FactorGraph::chi2() const {
  double s = 0.0;
  for (const auto& f : factors_) s += f->chi2();
  return s;
}

}  // namespace abi_v1
}  // namespace plugslam
