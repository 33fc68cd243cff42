#pragma once
// A factor graph: owns its variables (by unique user id) and its factors.
#include <memory>
#include <string>
#include <unordered_map>
#include <vector>

#include "plugslam/errors.h"
#include "plugslam/solver/factor.h"
#include "plugslam/solver/variable.h"

namespace plugslam {
inline namespace abi_v1 {

/// Variables and factors of one optimisation problem.
class FactorGraph {
 public:
  FactorGraph() = default;
  FactorGraph(const FactorGraph&) = delete;
  FactorGraph& operator=(const FactorGraph&) = delete;
  FactorGraph(FactorGraph&&) = default;
  FactorGraph& operator=(FactorGraph&&) = default;

  /// Adds a variable V(id, args...); throws InputError if the id is taken.
  template <class V, class... Args>
  V& addVariable(int64_t id, Args&&... args) {
    auto v = std::make_unique<V>(id, std::forward<Args>(args)...);
    V& ref = *v;
    insertVariable(std::move(v));
    return ref;
  }
  /// Adds a factor and returns it; its variables must belong to this graph.
  template <class F>
  F& addFactor(std::unique_ptr<F> factor) {
    F& ref = *factor;
    insertFactor(std::move(factor));
    return ref;
  }
  /// Constructs a factor F(args...) in place and returns it.
  template <class F, class... Args>
  F& emplaceFactor(Args&&... args) {
    return addFactor(std::make_unique<F>(std::forward<Args>(args)...));
  }

  /// The variable with this id, or nullptr.
  Variable* findVariable(int64_t id) const {
    auto it = index_.find(id);
    return it == index_.end() ? nullptr : it->second;
  }
  /// The variable with this id as a V; throws InputError if absent or of another type.
  template <class V>
  V& get(int64_t id) const {
    Variable* v = findVariable(id);
    if (!v) throw InputError("no variable with id " + std::to_string(id));
    V* typed = dynamic_cast<V*>(v);
    if (!typed) {
      throw InputError("variable " + std::to_string(id) + " is a " + v->typeName() +
                       ", not the type requested");
    }
    return *typed;
  }
  /// The variable of a typed id.
  template <class V>
  V& get(VariableId<V> id) const {
    return get<V>(id.value);
  }

  /// Variables in insertion order.
  const std::vector<Variable*>& variables() const { return order_; }
  /// Factors in insertion order.
  const std::vector<std::unique_ptr<FactorBase>>& factors() const { return factors_; }
  /// Number of variables.
  size_t numVariables() const { return order_.size(); }
  /// Number of factors.
  size_t numFactors() const { return factors_.size(); }
  /// Removes every factor, keeping the variables (an aligner rebuilds its factors each round).
  void clearFactors() { factors_.clear(); }
  /// Removes everything.
  void clear();
  /// Sum of robust costs over all factors at the current estimates.
  double robustChi2() const;
  /// Sum of e^T Omega e over all factors at the current estimates (no kernel).
  double chi2() const;

 private:
  void insertVariable(std::unique_ptr<Variable> v);
  void insertFactor(std::unique_ptr<FactorBase> f);

  std::vector<std::unique_ptr<Variable>> owned_;
  std::vector<Variable*> order_;
  std::unordered_map<int64_t, Variable*> index_;
  std::vector<std::unique_ptr<FactorBase>> factors_;
};

}  // namespace abi_v1
}  // namespace plugslam
