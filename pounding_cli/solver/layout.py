"""The column layouts of the arrays the time loop hands back: the energy account, each contact
pair's current values and the impact log. Plain constants, no numba: the results, the
readers and `pound validate` use them without loading the compiled kernels."""

from __future__ import annotations

# energy columns, in the order of the HDF5 /energy dataset
E_INPUT, E_KINETIC, E_STRAIN, E_DAMPING, E_HYSTERETIC, E_CONTACT, E_BALANCE = range(7)
ENERGY_NAMES = ("input", "kinetic", "strain", "damping", "hysteretic", "contact", "balance_error")

# per-pair current values (also what is stored at the output interval)
NOW_FN, NOW_FT, NOW_AREA, NOW_X, NOW_Y, NOW_DEPTH = range(6)
NOW_COLUMNS = ("normal_force", "tangential_force", "area", "x", "y", "depth")
# impact log columns; EV_PEAK_FN: the episode's peak normal force, the crest of the parabola
# through the three steps around its largest sample (crest); EV_T_PEAK, EV_X, EV_Y,
# EV_FT_PEAK (F_T on B along t), EV_NX, EV_NY (n from A into B) are taken at the step of the
# largest sample; EV_PEAK_LENGTH: the longest
# contact line of the episode, m (its normal stiffness k_N·length: the automatic contact step
# is checked against it, assembly/contact.py: observed_pair_omega)
EV_PAIR, EV_T_START, EV_T_END, EV_PEAK_FN, EV_IMPULSE, EV_PEAK_AREA, EV_PEAK_DEPTH, EV_X, EV_Y, EV_SLID, EV_T_PEAK = range(11)
EV_FT_PEAK, EV_NX, EV_NY, EV_PEAK_LENGTH = range(11, 15)
# EV_T_SLIP: where the contact first slipped (t_start if from the touch), EV_T_STICK: where its
# last slip ended (NaN: never slipped, or slipping to the end), EV_SLIPS: how many slip phases;
# these and t_start, t_end are located inside their steps (docs/theory.md, "Events inside the step")
EV_T_SLIP, EV_T_STICK, EV_SLIPS = range(15, 18)
EV_COLUMNS = 18
