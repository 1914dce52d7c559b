#include "x2car/core/extrinsic.hpp"

#include <stdexcept>

namespace x2car {

Extrinsic inverse(const Extrinsic& parent_from_child) {
  return {parent_from_child.child_frame, parent_from_child.parent_frame,
          parent_from_child.parent_from_child.inverse()};
}

Extrinsic compose(const Extrinsic& a_from_b, const Extrinsic& b_from_c) {
  if (a_from_b.child_frame != b_from_c.parent_frame) {
    throw std::invalid_argument("cannot compose " + a_from_b.parent_frame + "_from_" +
                                a_from_b.child_frame + " with " + b_from_c.parent_frame + "_from_" +
                                b_from_c.child_frame + ": the frames do not chain");
  }
  return {a_from_b.parent_frame, b_from_c.child_frame,
          a_from_b.parent_from_child * b_from_c.parent_from_child};
}

}  // namespace x2car
