import math

import pytest

from dyntorsion import Rod


def test_table1_values():
    r = Rod()
    assert r == Rod.paper()
    assert r.G == pytest.approx(1.25e7 / 2.5, rel=1e-15)
    assert r.A == pytest.approx(math.pi * 1e-6 / 4, rel=1e-15)
    assert r.I1 == r.I2 == pytest.approx(r.A * 1e-6 / 16, rel=1e-15)
    assert r.J == pytest.approx(2 * r.I1, rel=1e-15)
    assert r.B1 == pytest.approx(r.E * r.I1) and r.C == pytest.approx(r.G * r.J)
    # c = 57.74 m/s (section 5) and T = 4L/c = 0.06928 s (section 7)
    assert r.c == pytest.approx(57.735, abs=5e-4)
    assert round(r.c, 2) == 57.74
    assert round(r.T1, 5) == 0.06928


def test_derived_follow_changes():
    r = Rod().with_(rho=5000.0)
    assert r.c == pytest.approx(math.sqrt(r.G / 5000.0))
    assert r.mass_per_length == pytest.approx(5000.0 * r.A)


@pytest.mark.parametrize(
    "name,value",
    [
        ("E", 0.0),
        ("E", -1.0),
        ("nu", -1.0),
        ("nu", 0.6),
        ("D", 0.0),
        ("L", -2.0),
        ("rho", 0.0),
        ("E", float("nan")),
        ("L", float("inf")),
    ],
)
def test_bad_parameters_name_the_parameter(name, value):
    with pytest.raises(ValueError, match=rf"\b{name}=.*allowed range"):
        Rod(**{name: value})
