"""Integer tooth counts of a gear train at fixed centre distances: enumerate, fit by profile shift, optimise, rank.

The thesis (section 3.4.1, Eq. 3.1, Table 3.1) converted a helical timing train to spur gears in the same housing:
tooth counts z = d/m at the spur module, a 2.7027 % speed-ratio error accepted on the lube pump branch,
centre distances closed by profile shift (section 3.4.2). Here that choice is made systematically:

1. **Enumerate** integer tooth counts per gear (a range or ``span`` around the train's teeth), walking the train's
   tree from its root gear so each mesh is checked as soon as both its gears have teeth. A partial assignment that
   fails is reported once in :attr:`ToothCountEnumeration.rejected` (it stands for every completion of it), with
   the stage and the reason:

   - ``speed_ratio``: a mesh's ratio ``n2/n1 = z1/z2`` or a gear's speed relative to the root ``z_root/z_gear``
     (intermediate idlers cancel) differs from the reference by more than its tolerance [%];
   - ``centre_distance``: the housing's centre distance cannot be reached (no working pressure angle in
     (0, 45] deg, ISO 21771 eq. 46);
   - ``sum_of_shifts``: the sum of profile shifts x1 + x2 that closes the centre distance (ISO 21771 eq. 44, thesis
     Eqs. 3.2-3.5) lies outside the sum of the two gears' lower limits (ISO/TR 4467 recommended lower limit, thesis
     Eqs. 3.8-3.12, or the undercut limit, whichever is higher) and upper limits (ISO/TR 4467 upper limit);
   - ``shift_limits``: with every mesh's sum fixed, each gear's shift is ``x_g = s_g +- x_root`` (x_root: the root
     gear's shift, the one free split of the tree). The per-gear limits give an interval of x_root; empty = rejected,
     naming the two gears whose limits conflict;
   - ``precheck``: sampled feasibility of the nonlinear limits (worst-case contact ratio, tip thickness,
     interference, bottom clearance, backlash) at ``precheck_samples`` root shifts evenly spread over the interval.
     A sampled check: a candidate feasible only inside a window narrower than the sample spacing would be rejected
     (spacing reported in the reason; ``precheck=False`` sends every interval-feasible candidate to the NLP).

2. **Optimise** each admissible candidate with Ipopt (:class:`~gearopt.nlp.problem.Problem`): variable = the root
   gear's profile shift x_root within its interval (the rest of the tree follows, :class:`GearTrain`), constraints =
   every mesh's :meth:`GearPair.constraints` (worst-case contact ratio, tip thickness, undercut, interference,
   bottom clearance, ISO/TR 4467 limits, backlash; per-gear limits once per gear), objective = the smallest
   worst-case transverse contact ratio of all meshes, or the smallest normal tip thickness of all gears [mm]
   (epigraph form, maximised). Candidates are solved in enumeration order, each warm-started at the previous
   candidate's optimal x_root (clipped into its own interval); cold start = the train's ISO/TR 4467 split; or
   each starts at its best precheck sample. (Each candidate has its own NLP, so only the primal start carries
   over: the constraint sets differ in size between candidates.)
   A failed solve is kept in the table with its typed error's status and the violated constraints by name.

3. **Rank** by the objective (best first), ties by the largest absolute speed-ratio error.

Optionally, :func:`bonmin_cross_check` solves a relaxed mixed-integer model (integer teeth, the speed-ratio
tolerances as linear constraints, the sums of shifts as continuous functions of the tooth sums, the per-gear shift
limits as piecewise-linear functions of z; objective: the widest margin to the shift limits) with CasADi's Bonmin
and compares its integer solution with the enumeration's best candidate by the same measure.

Conventions: angles in degrees, lengths in mm, profile shifts and contact ratios dimensionless, speed-ratio errors
in percent (``(candidate / reference - 1) * 100``). Speed ratios here are magnitudes (the sense of rotation is
fixed by the tree). Validity: external involute gears, teeth >= 5, the train's rack and helix angle.
"""

from .candidates import (OBJECTIVES, REFERENCES, STAGES, CandidateModel, _train_with_teeth,  # noqa: F401
                         candidate_model,
                         gear_shift_limits, mesh_sum_of_shifts, reference_speed_ratios)
from .enumeration import ToothCountEnumeration, enumerate_tooth_counts
from .study import STARTS, ToothCountStudy, solve_candidate, tooth_count_study
from .bonmin import _iso_limits_relaxed, bonmin_cross_check  # noqa: F401 (tests use the private helpers)

__all__ = ["OBJECTIVES", "REFERENCES", "STAGES", "STARTS", "CandidateModel", "candidate_model", "gear_shift_limits",
           "mesh_sum_of_shifts", "reference_speed_ratios", "ToothCountEnumeration", "enumerate_tooth_counts",
           "ToothCountStudy", "solve_candidate", "tooth_count_study", "bonmin_cross_check"]
