// The relaxed models' tally of one call's differing elements (spec_model.cpp, spec_tree.cpp).
#pragma once
#include <string>

#include "rayspace/verify/spec_model.h"

namespace rayspace::verify {

class SpecTally {
 public:
  SpecTally() { v_.modelled = true; }
  void Within() { ++v_.within; }
  void Beyond(const std::string& why) {
    if (v_.beyond++ == 0) v_.first_beyond = why;
  }
  SpecVerdict Done() { return v_; }

 private:
  SpecVerdict v_;
};

// The models of the object-tree descent's passes (tree.roots, tree.expand, tree.test, tree.step), or
// an unmodelled verdict for another method.
SpecVerdict ClassifyTree(const std::string& method, const BufferSet& in, const BufferSet& expected, const BufferSet& actual,
                         bool flush_denormals);

}  // namespace rayspace::verify
