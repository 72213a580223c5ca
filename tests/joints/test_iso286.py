"""ISO 286 fit table against published fits (Shigley's solutions) and the default data's [V] deviations."""

import pytest

from gearopt.data import load_default_data, values
from gearopt.errors import GearoptInputError
from gearopt.joints.iso286 import fit_interference_um, hole_deviations_um, shaft_deviations_um, tolerance_grade_um


def test_shigley_solutions_40mm_s6_and_u6_fits():
    # Shigley's MED solutions manual 3-64 and 3-66 (coursehero excerpt "47-ch-03 budynas SM ch03"), 40 mm H7 hub:
    # 3-64 shaft 40.043..40.059 (s6) with hub 40.000..40.025 -> radial delta 0.009..0.0295 mm;
    # 3-66 shaft 40.060..40.076 (u6) -> radial delta 0.0175..0.038 mm.
    s = fit_interference_um(40.0, "H7/s6")
    assert (s["shaft_lower_um"], s["shaft_upper_um"], s["hole_upper_um"]) == (43.0, 59.0, 25.0)
    assert (s["min_um"], s["max_um"]) == (2 * 9.0, 2 * 29.5)
    u = fit_interference_um(40.0, "H7/u6")
    assert (u["min_um"], u["max_um"]) == (2 * 17.5, 2 * 38.0)


def test_default_data_fits_reproduced():
    d = values(load_default_data())["joints"]
    n = 0
    for name, j in d.items():
        if j["joint_type"] != "press_fit":
            continue
        f = fit_interference_um(j["shaft_diameter_mm"], j["fit"])
        assert (f["hole_lower_um"], f["hole_upper_um"]) == (j["hub_bore_lower_deviation_um"],
                                                            j["hub_bore_upper_deviation_um"]), name
        assert (f["shaft_lower_um"], f["shaft_upper_um"]) == (j["shaft_lower_deviation_um"],
                                                              j["shaft_upper_deviation_um"]), name
        assert (f["min_um"], f["max_um"], f["mean_um"]) == (j["diametral_interference_min_um"],
                                                            j["diametral_interference_max_um"],
                                                            j["diametral_interference_um"]), name
        n += 1
    assert n == 4


def test_range_boundaries_are_up_to_and_including():
    assert tolerance_grade_um(50.0, 7) == 25.0 and tolerance_grade_um(50.001, 7) == 30.0
    assert shaft_deviations_um(65.0, "s6") == (53.0, 72.0) and shaft_deviations_um(65.5, "s6") == (59.0, 78.0)
    assert hole_deviations_um(22.0, "H8") == (0.0, 33.0)


def test_errors_name_the_limit():
    with pytest.raises(GearoptInputError, match="nominal_mm=200 mm is outside"):
        fit_interference_um(200.0, "H7/r6")
    with pytest.raises(GearoptInputError, match="only H holes"):
        hole_deviations_um(40.0, "G7")
    with pytest.raises(GearoptInputError, match="only shafts"):
        shaft_deviations_um(40.0, "k6")
    with pytest.raises(GearoptInputError, match="not defined by ISO 286 at 20 mm"):
        shaft_deviations_um(20.0, "t6")
    with pytest.raises(GearoptInputError, match="IT9 is not tabulated"):
        tolerance_grade_um(40.0, 9)
