#pragma once
// The energy's terms (optim/problem.h), each added to a PoseProblem by a function of its own:
// its constraints (optim/constraints.h) become residual blocks under its Term, weighted as
// problem.h says, on the poses' blocks and, for the structural model, on plane variables that
// live here. SolvePoses (optim/problem.cc) calls them in the order of AddAll. Internal to
// optim/. A new term: its cost function (cost_functions.h), its constraints, a Term, a
// function here, a line in AddAll (docs/architecture.md).

#include <vector>

#include "f2c/optim/constraints.h"
#include "f2c/optim/pose_problem.h"
#include "f2c/optim/problem.h"

namespace f2c {

class Energy {
 public:
  // `poses` and `problem` must outlive the Energy; the poses are already the problem's
  // variables. `previous`: the poses before this solve (E_I's reference).
  Energy(const Constraints& constraints, const SolverOptions& options, const PoseVector& previous, PoseVector* poses,
         PoseProblem* problem);

  // Every term, in the order their blocks enter the problem. The order fixes the order of the
  // normal equations' sums: listing the terms otherwise changes the result's last bits.
  void AddAll(int first_free_pose) {
    AddCorrespondences();
    AddLocal();
    AddSteadyMotion();
    AddMatches();
    AddStructure();
    AddInertia(first_free_pose);
  }

  void AddCorrespondences();        // E_C
  void AddLocal();                  // E_L
  void AddSteadyMotion();           // E_V
  void AddMatches();                // E_M
  void AddStructure();              // the planes, E_P, E_H, E_G
  void AddInertia(int first_free);  // E_I: poses from first_free on, and the parents

  // The structural model's planes joined the problem (w_P > 0 and a model to solve).
  bool has_structure() const { return use_structure_; }

 private:
  std::vector<double*> PairBlocks(int a, int b);

  const Constraints& constraints_;
  const SolverOptions& options_;
  const PoseVector& previous_;
  PoseVector& poses_;
  PoseProblem& problem_;
  int n_ = 0;
  bool use_structure_ = false;
  // The structural model's plane variables: per-image children and world parents. Sized once,
  // so the problem's pointers into them stay valid.
  std::vector<PlaneVariable> children_, parents_;
};

}  // namespace f2c
