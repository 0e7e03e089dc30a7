// SignalSubtract: one of the signal components; SignalComponent.hpp's opening comment gives their equations and sources.
#pragma once

#include <algorithm>
#include <cmath>

#include "components/bilinear.hpp"
#include "component.hpp"
#include "table.hpp"
#include "components/signal/SignalAdd.hpp"

namespace tlm {

class SignalSubtract : public SignalAdd {
 public:
  using SignalAdd::SignalAdd;
  const char* type_name() const override { return "SignalSubtract"; }

 private:
  double value(double) override { return *u1_ - *u2_; }
};

}  // namespace tlm
