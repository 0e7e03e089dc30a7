// SignalTable: one of the signal components; SignalComponent.hpp's opening comment gives their equations and sources.
#pragma once

#include <algorithm>
#include <cmath>

#include "components/bilinear.hpp"
#include "component.hpp"
#include "table.hpp"
#include "components/signal/SignalComponent.hpp"

namespace tlm {

class SignalTable : public SignalComponent {
 public:
  using SignalComponent::SignalComponent;
  const char* type_name() const override { return "SignalTable"; }
  void configure(ParameterSet& p) override {
    table_ = Table(p.text("table", ""), p.where(), name_ + ": table");
    add_output();
  }

 private:
  double value(double t) override { return table_(t); }
  Table table_;
};

}  // namespace tlm
