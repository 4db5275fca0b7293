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
        s2 = float(onsager_solution(_area(np.abs(np.sin(PHI))), 3 * math.pi / 2 * (1 + excess)).order_parameter[1])
        slopes.append(s2**2 / excess)
    assert max(slopes) / min(slopes) < 1.05
    below = float(onsager_solution(_area(np.abs(np.sin(PHI))), 0.98 * 3 * math.pi / 2).order_parameter.sel(k=2))
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
    assert int(needles.transition_order) == 2 and int(needles.continuous) == 1
    density = float(needles.transition_density)
    assert density == pytest.approx(3 * math.pi / 2, rel=1e-3) == float(needles.ordered_density)
    assert 0 <= float(needles.transition_density_error) < 1e-3 * density  # ρ*₂'s own bar: the exact |sin φ|
    assert int(first_transition(_area(np.full(512, 4 * math.pi))).transition_order) == 0
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
    labels = [t.get_text() for t in fig.legends[0].get_texts()]
    assert labels == ["nematic", "continuous", "first order", "no transition"]  # the circle's opening is said
    density, gaps = fig.axes  # the gaps of first-order transitions below, on their own scale
    assert [t.get_text() for t in gaps.texts] == ["every transition continuous"]
    crosses = [line for line in density.lines if line.get_marker() == "x"]
    assert len(crosses) == 1 and list(crosses[0].get_xdata()) == [0.0]


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


def test_parsons_lee_thermodynamics_of_the_isotropic_state_are_the_hard_disk_fluid_s():
    """Isotropic hard disks (E = ⟨A_ex⟩ = 4a): the Parsons–Lee pressure and chemical potential are the
    scaled-particle theory's, βP/ρ = 1/(1 − η)² and βμ − ln ρ = −ln(1 − η) + η(3 − 2η)/(1 − η)²; at a = 0 the
    second-virial ρ + ρ²E/2 and ln ρ + ρE."""
    a = 0.3
    for eta in (0.05, 0.4, 0.8):
        rho = eta / a
        found = onsager_solution(_area(np.full(len(PHI), 4 * a)), rho, particle_area=a)  # isotropic: ψ = 1/2π
        pressure, potential = float(found.pressure), float(found.chemical_potential)
        assert pressure / rho == pytest.approx(1 / (1 - eta) ** 2, rel=1e-12)
        excess = -math.log(1 - eta) + eta * (3 - 2 * eta) / (1 - eta) ** 2
        assert potential - math.log(rho) == pytest.approx(excess, rel=1e-9)
        assert potential == pytest.approx(float(found.free_energy) + pressure / rho)
    plain = onsager_solution(_area(np.full(len(PHI), 3.0)), 2.0)
    assert (float(plain.pressure), float(plain.chemical_potential)) == pytest.approx((2 + 4 * 1.5, math.log(2) + 6))


@pytest.mark.slow
def test_parsons_lee_coexistence_is_a_common_tangent_and_tends_to_onsager_s_as_the_area_vanishes():
    """Rectangles L/D = 2.5 (first-order nematic): with the rectangle's area a = LD the Parsons–Lee bifurcation
    is the mapped second-virial one, the coexisting densities lie lower, and they are a common tangent of
    ρ βF/N of the two branches (checked on the stored free energies); a → 0 gives the second-virial gap."""
    from sesp.onsager import parsons_lee_density

    area = _rectangle_area(2.5, 1.0)
    onsager = phase_behaviour(area, orders=(2, 4)).sel(order=2)
    found = phase_behaviour(area, orders=(2, 4), particle_area=2.5).sel(order=2)
    assert int(found.continuous) == 0
    assert float(found.bifurcation_density) == pytest.approx(
        float(parsons_lee_density(float(onsager.bifurcation_density), 2.5)), rel=1e-12
    )
    low, high = float(found.coexistence_low), float(found.coexistence_high)
    assert low < high < float(found.bifurcation_density) and high < float(onsager.coexistence_low)
    # the common tangent, from the stored free energies: f(ρ) = ρ βF/N, isotropic by its closed form
    rho = found.density.values
    ordered = found.free_energy.where(found.order_parameter != 0).values
    f_ordered = np.interp(high, rho[np.isfinite(ordered)], (rho * ordered)[np.isfinite(ordered)])
    mean = float(area.mean())

    def f_iso(r):  # ρ βF/N of the isotropic state: ρ (ln ρ − 1) + ρ² G(ρa) ⟨A_ex⟩/2
        eta = r * 2.5
        return r * (math.log(r) - 1) + r * (-math.log1p(-eta) + eta / (1 - eta)) / (2 * 2.5) * mean / 2

    h = 1e-6 * low
    slope = (f_iso(low + h) - f_iso(low - h)) / (2 * h)
    assert f_ordered == pytest.approx(f_iso(low) + slope * (high - low), rel=2e-4)
    tiny = phase_behaviour(area, orders=(2, 4), particle_area=1e-9).sel(order=2)
    for name in ("coexistence_low", "coexistence_high"):
        assert float(tiny[name]) == pytest.approx(float(onsager[name]), rel=1e-6)
