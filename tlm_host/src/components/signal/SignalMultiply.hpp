// SignalMultiply: one of the signal components; SignalComponent.hpp's opening comment gives their equations and sources.
#pragma once

#include "components/signal/SignalAdd.hpp"

namespace tlm {

// SignalAdd's two inputs, their product (evaluated in the model's order, as SignalAdd).
class SignalMultiply : public SignalAdd {
 public:
  using SignalAdd::SignalAdd;
  const char* type_name() const override { return "SignalMultiply"; }

 private:
  double value(double) override { return *u1_ * *u2_; }
};

}  // namespace tlm
