// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// A muparser expression of named variables, for initial fields and boundary values.

#include <memory>
#include <string>
#include <vector>

namespace mu {
class Parser;
}

namespace smpm {

/// Copies parse their own parser with their own variables: a copied Model (one per thread of
/// `smpm stability`) never shares an evaluation with the original.
class Expression {
public:
  /// Parses `text` with the variables `names` (and the constant pi). Throws InputError
  /// "<where>: cannot parse '<text>': <reason>".
  Expression(const std::string& text, const std::vector<std::string>& names,
             const std::string& where);
  ~Expression();
  Expression(const Expression& other);
  Expression& operator=(const Expression& other);
  Expression(Expression&&) noexcept;
  Expression& operator=(Expression&&) noexcept;

  /// Value for the variables in the order given to the constructor.
  double operator()(const double* values) const;
  const std::string& text() const { return text_; }

private:
  std::string text_;
  std::vector<std::string> names_;
  std::unique_ptr<mu::Parser> parser_;
  std::unique_ptr<double[]> slots_;
  size_t count_ = 0;
};

} // namespace smpm
