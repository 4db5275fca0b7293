"""The Onsager solution past the bifurcation: 2D needles and hard rectangles against their closed forms."""

import math

import numpy as np
import pytest
import xarray as xr

import sesp
from sesp.onsager import first_transition, onsager_solution, phase_behaviour

PHI = 2 * np.pi * np.arange(512) / 512


def _area(values):
    return xr.DataArray(values, coords={"phi": PHI}, dims="phi")


def _rectangle_area(length, width):
    """A_ex(φ) of two hard L × D rectangles: (L² + D²)|sin φ| + 2LD(1 + |cos φ|)."""
    return _area((length**2 + width**2) * np.abs(np.sin(PHI)) + 2 * length * width * (1 + np.abs(np.cos(PHI))))


def test_needles_order_continuously_at_three_pi_over_two():
    """Thin needles of length L = 1: the isotropic state is stable below ρL² = 3π/2 and the nematic order
    grows continuously above it, S₂ ∝ (ρ/ρ* − 1)^½."""
    found = phase_behaviour(_area(np.abs(np.sin(PHI))), orders=(2, 4))
    assert float(found.bifurcation_density.sel(order=2)) == pytest.approx(3 * math.pi / 2, rel=1e-3)
    assert int(found.continuous.sel(order=2)) == 1
    below = found.density < 0.99 * 3 * math.pi / 2
    assert (found.stable_order.where(below, drop=True) == 0).all()
    assert (found.stable_order.where(found.density > 1.02 * 3 * math.pi / 2, drop=True) == 2).all()
    slopes = []
    for excess in (0.005, 0.01, 0.02):
        s2 = onsager_solution(_area(np.abs(np.sin(PHI))), 3 * math.pi / 2 * (1 + excess))["order"][1]
        slopes.append(s2**2 / excess)
    assert max(slopes) / min(slopes) < 1.05
    below = onsager_solution(_area(np.abs(np.sin(PHI))), 0.98 * 3 * math.pi / 2)["order"][1]
    assert abs(below) < 1e-6  # the solver stops within 1e-10 of ψ: ⟨cos 2φ⟩ within 1e-6 of 0


@pytest.mark.parametrize("aspect, first", [(2.0, 4), (4.0, 2)])
def test_rectangles_order_first_as_the_closed_forms_say(aspect, first):
    """ρ*₂ = 3π / [2(L − D)²], ρ*₄ = 15π / [2(L + D)²]: tetratic first below L/D = (3 + √5)/2, nematic above."""
    found = phase_behaviour(_rectangle_area(aspect, 1.0), orders=(2, 4))
    assert float(found.bifurcation_density.sel(order=2)) == pytest.approx(
        3 * math.pi / (2 * (aspect - 1) ** 2), rel=1e-3
    )
    assert float(found.bifurcation_density.sel(order=4)) == pytest.approx(
        15 * math.pi / (2 * (aspect + 1) ** 2), rel=1e-3
    )
    ordered = found.stable_order.where(found.stable_order > 0, drop=True)
    assert int(ordered[0]) == first


def test_the_rectangle_s_own_excluded_area_gives_the_closed_form_bifurcations():
    """sesp's A_ex(φ) of a 4 × 1 rectangle (a closed polyline) gives ρ*₂ and ρ*₄ of the closed forms."""
    from sesp.onsager import instabilities

    rectangle = sesp.Polyline([[-2, -0.5], [2, -0.5], [2, 0.5], [-2, 0.5], [-2, -0.5]])
    found = instabilities(sesp.excluded_area(rectangle, rtol=1e-4), (2, 4))
    assert float(found.density.sel(order=2)) == pytest.approx(3 * math.pi / 18, rel=1e-3)
    assert float(found.density.sel(order=4)) == pytest.approx(15 * math.pi / 50, rel=1e-3)


def test_a_shape_that_never_orders_is_a_clear_error():
    with pytest.raises(ValueError, match="never becomes unstable"):
        phase_behaviour(_area(np.full(512, 4 * math.pi)))


def test_first_transition_and_its_figure(tmp_path):
    """Needles: nematic, continuous, at 3π/2; a closed circle: none; the figure draws both."""
    needles = first_transition(_area(np.abs(np.sin(PHI))))
    assert needles["order"] == 2 and needles["continuous"]
    assert needles["density"] == pytest.approx(3 * math.pi / 2, rel=1e-3) == needles["ordered_density"]
    assert first_transition(_area(np.full(512, 4 * math.pi)))["order"] == 0
    ds = xr.Dataset(
        {
            "transition_density": (("n", "opening"), [[3 * math.pi / 2, math.nan]]),
            "ordered_density": (("n", "opening"), [[3 * math.pi / 2, math.nan]]),
            "transition_order": (("n", "opening"), [[2, 0]]),
            "continuous": (("n", "opening"), [[1, 0]]),
        },
        coords={"n": [2], "opening": [math.pi, 0.0]},
    )
    import matplotlib

    matplotlib.use("Agg")
    fig = sesp.plot.phase_diagram(ds)
    sesp.plot.save_figure(fig, tmp_path / "phases.png")
    assert (tmp_path / "phases.png").stat().st_size > 10_000


@pytest.mark.parametrize("aspect", [2.5, 2.7])
def test_near_the_crossover_the_nematic_transition_is_first_order(aspect):
    """Where ρ*₂ and ρ*₄ lie close (L/D near (3 + √5)/2), the nematic branch reaches below its bifurcation: the
    isotropic state coexists with a nematic one at lower densities (docs/findings.md)."""
    found = phase_behaviour(_rectangle_area(aspect, 1.0), orders=(2, 4)).sel(order=2)
    assert int(found.continuous) == 0
    assert float(found.coexistence_low) < float(found.coexistence_high) < float(found.bifurcation_density)


def test_parsons_lee_factor_gives_the_hard_disk_equation_of_state():
    """Hard disks of area a (A_ex = 4a, isotropic): the rescaled second-virial excess free energy
    2η G(η) differentiated, βP/ρ = 1 + η d(2ηG)/dη, is the scaled-particle equation of state 1/(1 − η)²; and
    G = 1 + 3η/4 + 2η²/3 + ... at low packing."""
    from sesp.onsager import parsons_lee_factor

    for eta in (0.05, 0.3, 0.6, 0.85):
        h = 1e-6
        slope = ((eta + h) * parsons_lee_factor(eta + h) - (eta - h) * parsons_lee_factor(eta - h)) / h  # d(2ηG)/dη
        assert 1 + eta * slope == pytest.approx(1 / (1 - eta) ** 2, rel=1e-7)
    assert parsons_lee_factor(0.0) == 1.0
    assert parsons_lee_factor(1e-3) == pytest.approx(1 + 0.75e-3 + 2e-6 / 3, rel=1e-9)  # next: 5η³/8
    assert parsons_lee_factor(1e-12) == pytest.approx(1 + 0.75e-12, rel=1e-15)
    with pytest.raises(ValueError, match="packing_fraction"):
        parsons_lee_factor(1.0)


def test_parsons_lee_density_maps_a_bifurcation_and_keeps_thin_particles():
    from sesp.onsager import parsons_lee_density, parsons_lee_factor, particle_area

    rho = parsons_lee_density(np.array([0.5, 3.0]), 0.2)
    assert rho * parsons_lee_factor(0.2 * rho) == pytest.approx([0.5, 3.0], rel=1e-12)
    assert np.all(rho < [0.5, 3.0])  # the hard-disk factor only raises the excess free energy
    assert parsons_lee_density(3 * math.pi / 2, 0.0) == 3 * math.pi / 2  # needles: no area, no change
    # an arc of radius 1, thickness D: the annular sector (1 + D/2)² − (1 − D/2)² over 2 times its angle, and
    # two half disks at its ends
    psi, d = math.radians(90), 0.1
    sector = ((1 + d / 2) ** 2 - (1 - d / 2) ** 2) / 2 * (2 * math.pi - psi)
    assert particle_area(sesp.SeSP(n=2, opening=psi, thickness=d)) == pytest.approx(
        sector + math.pi * d**2 / 4, rel=1e-9
    )
    assert particle_area(sesp.SeSP(n=2, opening=0.0, thickness=d)) == pytest.approx(2 * math.pi * d, rel=1e-9)
    assert particle_area(sesp.SeSP(n=2, opening=psi)) == 0.0
    needle = sesp.Polyline([[0, 0], [2, 0]], thickness=d)
    assert particle_area(needle) == pytest.approx(2 * d + math.pi * d**2 / 4)
