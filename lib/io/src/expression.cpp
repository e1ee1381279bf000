// SPDX-License-Identifier: BSD-3-Clause
#include "expression.hpp"

#include "sparsempm/errors.hpp"

#include <muParser.h>
#include <numbers>

namespace smpm {

Expression::Expression(const std::string& text, const std::vector<std::string>& names,
                       const std::string& where)
    : text_(text), names_(names), parser_(std::make_unique<mu::Parser>()),
      slots_(std::make_unique<double[]>(names.size() + 1)), count_(names.size()) {
  try {
    parser_->DefineConst("pi", std::numbers::pi);
    for (size_t k = 0; k < names.size(); ++k) {
      slots_[k] = 0;
      parser_->DefineVar(names[k], &slots_[k]);
    }
    parser_->SetExpr(text);
    parser_->Eval(); // parses now, so that errors surface while reading the input
  } catch (const mu::Parser::exception_type& e) {
    throw InputError(where + ": cannot parse '" + clip(text) + "': " + clip(e.GetMsg(), 160));
  }
}

Expression::~Expression() = default;
Expression::Expression(const Expression& other)
    : Expression(other.text_, other.names_, "copy of '" + other.text_ + "'") {}
Expression& Expression::operator=(const Expression& other) {
  if (this != &other)
    *this = Expression(other);
  return *this;
}
Expression::Expression(Expression&&) noexcept = default;
Expression& Expression::operator=(Expression&&) noexcept = default;

double Expression::operator()(const double* values) const {
  for (size_t k = 0; k < count_; ++k)
    slots_[k] = values[k];
  return parser_->Eval();
}

} // namespace smpm
