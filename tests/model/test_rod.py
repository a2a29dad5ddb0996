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


# ------------------------------------------------------------------ sections (issue 14)
from hypothesis import given, settings  # noqa: E402
from hypothesis import strategies as st  # noqa: E402

from dyntorsion.model.rod import Section  # noqa: E402

ANY = st.one_of(
    st.floats(allow_nan=True, allow_infinity=True),
    st.floats(min_value=1e-6, max_value=1e-2),
    st.integers(-3, 3),
    st.text(max_size=3),
    st.none(),
)


@settings(max_examples=200, deadline=None, derandomize=True)
@given(kind=st.sampled_from(["circle", "ellipse", "rectangle"]), x=ANY, y=ANY)
def test_any_section_input_gives_a_usable_rod_or_names_the_parameter(kind, x, y):
    try:
        if kind == "circle":
            rod = Rod(D=x)
        elif kind == "ellipse":
            rod = Rod.elliptic(a=x, b=y)
        else:
            rod = Rod.rectangular(w=x, h=y)
    except (TypeError, ValueError) as err:
        names = {"circle": ("D",), "ellipse": ("a", "b"), "rectangle": ("w", "h")}[kind]
        assert any(f"{n}=" in str(err) or f"'{n}'" in str(err) for n in names), str(err)
        return
    for v in (rod.B1, rod.B2, rod.C, rod.c, rod.T0, rod.mass_per_length, rod.thickness):
        assert math.isfinite(v) and v > 0


def test_elliptic_section_properties():
    a, b = 0.6e-3, 0.4e-3
    rod = Rod.elliptic(a=a, b=b)
    assert rod.I1 == pytest.approx(math.pi * a * b**3 / 4, rel=1e-15)
    assert rod.I2 == pytest.approx(math.pi * a**3 * b / 4, rel=1e-15)
    assert rod.J == pytest.approx(math.pi * a**3 * b**3 / (a**2 + b**2), rel=1e-15)
    assert rod.B1 < rod.B2 and rod.J < rod.I3
    assert rod.c == pytest.approx(math.sqrt(rod.C / rod.rotary_inertia[2]), rel=1e-15)
    assert rod.c < Rod().c  # the warping section is softer in torsion than its polar moment
    circle = Rod.elliptic(a=0.5e-3, b=0.5e-3)
    assert circle.params()["B1"] == pytest.approx(Rod().B1, rel=1e-15)
    assert circle.c == pytest.approx(Rod().c, rel=1e-15)


def test_rectangle_torsion_constant_matches_the_tabulated_values():
    """Saint-Venant's beta in J = beta w h^3 (Timoshenko & Goodier, table): 0.141 for a
    square, 0.229 for 2:1, 0.263 for 3:1, 0.281 for 4:1, 0.312 for 10:1."""
    for ratio, beta in ((1, 0.1406), (2, 0.229), (3, 0.263), (4, 0.281), (10, 0.312)):
        sec = Section.rectangle(ratio * 1e-3, 1e-3)
        assert sec.J / (ratio * 1e-12) == pytest.approx(beta, abs=2e-3), ratio


def test_scales_are_defined_once_on_the_rod():
    rod = Rod()
    assert rod.T0 == rod.L**2 * math.sqrt(rod.mass_per_length / rod.B1)
    assert rod.transit == rod.L / rod.c and rod.T1 == 4 * rod.L / rod.c
    assert rod.c == math.sqrt(rod.G / rod.rho)


def test_a_rod_given_by_its_properties_round_trips():
    rod = Rod.from_properties(
        L=2.0, B1=1e-6, B2=3e-6, C=2e-6, mass_per_length=2e-3,
        rotary_inertia=(1e-10, 3e-10, 4e-10), thickness=1e-3,
    )  # fmt: skip
    assert Rod.from_params(rod.params()) == rod
    assert rod.c == math.sqrt(2e-6 / 4e-10) and rod.B == 1e-6
    with pytest.raises(ValueError, match="no meaning"):
        Rod(E=1.0, D=None, section=rod.section)
