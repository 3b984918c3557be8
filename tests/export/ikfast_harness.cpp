// Calls an exported IKFast file as MoveIt's ikfast_kinematics_plugin does: the solver's
// .cpp included inside the plugin's namespace, ComputeIk on a translation and a row-major
// rotation with an IkSolutionList, each solution read with GetSolution. NAME, UPPER: the solver's name;
// NFREE: the free parameters it should have (a held joint: 1).
#include <cmath>
#include <list>
#include <stdexcept>
#include <vector>

namespace plugin {
#define IKFAST_NO_MAIN
#include "NAME_ikfast.cpp"
}  // namespace plugin

extern "C" {
// (solutions written to q, n) as the plugin gets them, the free parameters' values from
// free_values; -1 when a query says otherwise
int ikfast_solve(const double T[16], const double* free_values_in, double* q) {
  using namespace plugin;
  if (GetIkType() != 0x67000001 || GetNumJoints() != UPPER_IK_DOF ||
      GetNumFreeParameters() != NFREE || GetIkRealSize() != static_cast<int>(sizeof(double)))
    return -1;
  double trans[3] = {T[3], T[7], T[11]};
  double rot[9] = {T[0], T[1], T[2], T[4], T[5], T[6], T[8], T[9], T[10]};
  std::vector<double> vfree(GetNumFreeParameters());
  for (size_t i = 0; i < vfree.size(); i++) vfree[i] = free_values_in[i];
  IkSolutionList<IkReal> solutions;
  bool found = ComputeIk(trans, rot, vfree.size() > 0 ? &vfree[0] : nullptr, solutions);
  int n = static_cast<int>(solutions.GetNumSolutions());
  if (found != (n > 0)) return -1;
  for (int i = 0; i < n; i++) {
    const IkSolutionBase<IkReal>& sol = solutions.GetSolution(i);
    std::vector<IkReal> free_values(sol.GetFree().size());
    sol.GetSolution(q + i * UPPER_IK_DOF, free_values.size() > 0 ? &free_values[0] : nullptr);
  }
  return n;
}

// the index of the first free parameter's joint, -1 without one
int ikfast_free_index() {
  return plugin::GetNumFreeParameters() > 0 ? plugin::GetFreeParameters()[0] : -1;
}

void ikfast_fk(const double* q, double* trans, double* rot) { plugin::ComputeFk(q, trans, rot); }
}
