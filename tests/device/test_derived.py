"""Derived quantities are derived (issue #11 item 1): c1, c2, S_t follow the geometry.

The values pinned in :data:`PINNED` were printed by the code before the redesign
(branch params-derived, parent of the redesign commit); every preset must keep them.
"""

import pytest

from liquidamp.device import preset, preset_names

#: (c1 [kg m^-4 s^-1], c2 [kg m^-7], S_t [1/m], b_L [kg]) of each preset before the redesign.
PINNED = {
    "paper_initial": (1048506548.1355934, 135389539930555.56, 187500.0, 89.4054399519941),
    "paper_calibrated": (3732683311.3627124, 546973741319444.5, 187500.0, 89.4054399519941),
    "reference": (3732683311.3627124, 546973741319444.5, 187500.0, 89.4054399519941),
    "spring": (37326833113.62713, 5469737413194445.0, 18750.0, 8.94054399519941),
    "damper": (3732683311.3627124, 656368489583333.4, 18750.0, 8.94054399519941),
    "inerter": (3732683311.3627124, 546973741319444.5, 1312500.0, 625.8380796639588),
    "device_a": (1119804993.4088137, 164092122395833.34, 337500.0, 160.92979191358938),
    "device_b": (1119804993.4088137, 164092122395833.34, 18750.0, 8.94054399519941),
}


def test_pinned_presets_cover_every_preset():
    assert set(PINNED) == set(preset_names())


@pytest.mark.parametrize("name", sorted(PINNED))
def test_preset_values_unchanged(name):
    p = preset(name)
    for got, want in zip((p.c1, p.c2, p.S_t, p.b_L), PINNED[name], strict=True):
        assert got == pytest.approx(want, rel=1e-14)
