// The user-load hook: a one-method interface, called once per FE step at
// stage 2 of the explicit step (after internal forces, before contact and
// accelerations) with the positions x_n and the velocities v_{n-1/2}. It adds
// its external forces to f_ext. The solver accounts their work.
#pragma once

#include <vector>

#include "model.hpp"

namespace fe {

class UserLoad {
 public:
  virtual ~UserLoad() = default;
  virtual void apply(double t, const std::vector<Vec3>& x, const std::vector<Vec3>& v,
                     std::vector<Vec3>& f_ext) = 0;
};

}  // namespace fe
