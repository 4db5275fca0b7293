"""The third virial coefficient B₃ from the overlap indicators on a lattice, deterministically.

With particle 1 fixed at the origin and orientation 0, and f = −1 where two particles overlap (0 elsewhere),

    B₃ = −(1/3) ⟨∫∫ f₁₂ f₁₃ f₂₃ dr₂ dr₃⟩ = (1/3) ⟨∫∫ E₁₂(r₂) E₁₃(r₃) E₂₃(r₃ − r₂) dr₂ dr₃⟩,

E the overlap indicators and ⟨·⟩ the mean over the orientations φ₂, φ₃ of particles 2 and 3 (b⁴).

The lattice has a node at the origin and spacing h: nodes (i h, j h), |i|, |j| <= K, K h beyond the pair's
reach. E₁₂ and E₁₃ are the slices φ₂ and φ₃ of particle 1 against a turned particle. E₂₃(d) is particle 3,
turned by φ₃, against particle 2 turned by φ₂, decided by the same kernel on the same lattice with particle
2's vertices turned: the difference of two nodes is a node, so nothing is interpolated. The inner integral
over r₃ is a cross-correlation of two 0/1 arrays, done by FFT and rounded to the integer count it is, so the
result does not depend on the FFT's rounding. Orientations are φ_k = 2πk/nphi for both particles; with
``orientations="fixed"`` all three keep φ = 0 (parallel particles).

Particles 2 and 3 are placed on ``shifts`` lattices moved together by low-discrepancy shifts (the lattice of
their difference is unmoved), which turns the lattice's bias into scatter; the value is the mean over the
shifts. Error bar: the lattice part is the larger of twice the standard error over the shifts and the change
from the sublattice of every other node (spacing 2h, the same arrays subsampled: free; as large as the
error at h when that falls as h, which flat sides along the lattice's rows make it do); the orientation
part is the change from every other orientation. Their sum is an indication of the error, not a bound, as
for A_ex. Exact anchors in the tests: thin rings (their curves meet
exactly when hard disks of diameter 2R overlap: B₃/B₂² = 4/3 − √3/π) and parallel squares (B₃/B₂² = 3/4).
"""

from __future__ import annotations

import itertools
import math
import time
import warnings
from concurrent.futures import ThreadPoolExecutor

import numba
import numpy as np
import xarray as xr

from .checks import check_choice, check_count, check_rtol
from .field import overlaps
from .grid import available_memory
from .kernels.overlap import crossing_field
from .kernels.spectra import triple_sum
from .measures import RTOL, excluded_area, lattice_shifts
from .onsager import mixture_second_virial
from .pair import as_pair
from .progress import progress_bar
from .shape import DEFAULT_SEGMENTS
from .units import link_errors, quantity

__all__ = ["second_virial", "third_virial", "mixture_third_virial", "third_virial_monte_carlo", "ORIENTATIONS"]

ORIENTATIONS = ("free", "fixed")
B3_RTOL = 1e-3  # the relative error bar third_virial refines to by default
START = {"nodes": 129, "nphi": 32}  # the settings third_virial refines from
LARGEST = {"nodes": 1025, "nphi": 256}  # and the largest it refines to


def _lattice(reach: float, nodes: int) -> np.ndarray:
    """Node coordinates i·h, |i| <= K, with 2K + 1 = ``nodes`` (odd) and (K − 1) h just past ``reach`` (a lattice
    moved by up to half a cell still covers it); K even, so that the sublattice of every other node also holds
    the origin."""
    half = (nodes - 1) // 2
    half += half % 2
    return np.arange(-half, half + 1) * (reach * (1 + 1e-9) / (half - 1) + 1e-12)


def _overlaps(v1, v2, angle1: float, angle2: float, xs, pair, shift=(0.0, 0.0)) -> np.ndarray:
    """0/1 float array (y, x): particle 2 (vertices v2 turned by angle2) at each node, moved by ``shift`` (b),
    overlaps particle 1 (vertices v1 turned by angle1)."""
    c1, s1 = math.cos(angle1), math.sin(angle1)
    turned = np.ascontiguousarray(v1 @ np.array([[c1, s1], [-s1, c1]]))
    field = crossing_field(
        turned, v2, np.array([math.cos(angle2)]), np.array([math.sin(angle2)]), xs + shift[0], xs + shift[1],
        pair.tolerance,
        contact=pair.contact, reach=pair.reach,
    )  # fmt: skip
    return (field[0] > 0).astype(np.float64)


class _Correlator:
    """Σ_{r₂} E₁₂(r₂) Σ_{r₃} E₁₃(r₃) E₂₃(r₃ − r₂) in node counts, by FFT, on one lattice.

    On the lattice padded to P = 2·nodes (no wrap-around of differences up to ±(nodes − 1)), with the
    difference lattice centred at c = nodes // 2, the sum is (1/P²) Σ_f Ê₁₂(f) conj(Ê₁₃(f)) Ê₂₃(f) e^{2πi f·c/P}
    over all frequencies f: one product of three spectra, no inverse transform per triple. The count is a
    whole number; where rounding leaves it more than 1/4 from one, it is counted again through the inverse
    transform of Ê₁₃ conj(Ê₂₃), rounded node by node."""

    def __init__(self, nodes: int):
        self.nodes = nodes
        self.shape = (2 * nodes, 2 * nodes)
        size, centre = self.shape[0], nodes // 2
        turn = np.exp(2j * np.pi * centre * np.arange(size) / size)
        halves = np.full(size // 2 + 1, 2.0)  # rfft2 keeps half the columns: the others are conjugates
        halves[[0, -1]] = 1.0
        self.weights = turn[:, None] * (turn[: size // 2 + 1] * halves)[None, :] / size**2

    def spectrum(self, e: np.ndarray) -> np.ndarray:
        return np.fft.rfft2(e, s=self.shape)

    def triple(self, e12: np.ndarray, spectrum12, spectrum13: np.ndarray, spectrum23: np.ndarray) -> int:
        total = triple_sum(spectrum12, spectrum13, spectrum23, self.weights)
        if abs(total - round(total)) < 0.25:
            return int(round(total))
        g = np.fft.irfft2(spectrum13 * np.conj(spectrum23), s=self.shape)  # g[m] = Σ_p e13[p] e23[p − m]
        k = self.nodes // 2
        shifts = np.r_[np.arange(self.shape[0] - k, self.shape[0]), np.arange(0, k + 1)]  # m = −k .. k
        return int(np.rint((e12 * np.rint(g[np.ix_(shifts, shifts)])).sum()))


def second_virial(particles, fractions=None, *, rtol: float = RTOL) -> xr.Dataset:
    """B₂ of one species, or of a mixture, with its error bar (b²): ⟨A_ex⟩/2 of each pair of species from
    :func:`sesp.excluded_area` refined to ``rtol``, weighted by the mole fractions.

    ``particles``: a particle (SeSP or Polyline), or a list of them, one per species; ``fractions``: their mole
    fractions (summing to 1; default equal). One A_ex is measured per pair of species (i ≤ j).

    Returns
    -------
    xarray.Dataset
        As :func:`sesp.onsager.mixture_second_virial`: ``second_virial_coefficient`` ± ``_error`` (b²) and,
        per pair of species, ``second_virial_matrix`` ± ``_error``.

    Examples
    --------
    >>> from sesp import Polyline, SeSP
    >>> needle, ring = Polyline([[-1, 0], [1, 0]]), SeSP(n=2, opening=0.0)
    >>> found = second_virial([needle, ring], [0.5, 0.5], rtol=1e-3)
    >>> round(float(found.second_virial_matrix.sel(species_i=0, species_j=0)), 3)  # needles: L²·(2/π)/2 = 4/π
    1.273
    """
    species = list(particles) if isinstance(particles, list | tuple) else [particles]
    fractions = np.full(len(species), 1.0 / len(species)) if fractions is None else fractions
    areas = {}
    for i, a in enumerate(species):
        for j in range(i, len(species)):
            areas[i, j] = areas[j, i] = excluded_area(a, None if i == j else species[j], rtol=rtol, progress=False)
    return mixture_second_virial([[areas[i, j] for j in range(len(species))] for i in range(len(species))], fractions)


def third_virial(
    particle,
    second=None,
    third=None,
    *,
    rtol: float | None = B3_RTOL,
    nodes: int | None = None,
    nphi: int | None = None,
    shifts: int | None = None,
    orientations: str = "free",
    segments: int = DEFAULT_SEGMENTS,
    progress: bool = True,
    memory_limit: int | None = None,
) -> xr.Dataset:
    """B₃ of one species, or B₃,ᵢⱼₖ of three (a mixture), with an error bar, from the overlap indicators (b⁴).

    The settings left unset are refined from ``START``, each step raising the one whose part of the error bar is
    larger (``nodes`` to 2·nodes − 1 for the lattice part, ``nphi`` by 3/2 for the orientation part), until the
    error bar is at most ``rtol`` · |B₃|. Where that cannot be reached (a given setting's part dominates, or the
    next step would pass ``LARGEST`` or the memory limit) the result says so (attribute ``converged`` 0) and a
    warning tells how far it got.

    Parameters
    ----------
    particle, second, third
        Particles 1, 2 and 3 (SeSP or Polyline; ``second`` and ``third`` default to ``particle``).
    rtol : float or None
        Relative error bar of B₃ to reach (default 1e-3); None: one evaluation at the start settings.
    nodes : int, optional
        Lattice nodes along each axis (odd; the lattice spans the reach of the widest pair); refined from 129
        if unset. The cost is nphi² FFTs of (2·nodes)² points; the lattice error falls roughly as 1/nodes^1.5.
    nphi : int, optional
        Orientations per particle, φ = 2πk/nphi (even, so that every other one is a coarser rule); refined from
        32 if unset.
    shifts : int, optional
        Lattices for particles 2 and 3 moved together by a low-discrepancy shift (their difference, where E₂₃
        is decided, stays on the lattice): the mean is the value, the scatter part of the error bar. Default
        4 for free orientations; 1 for fixed ones, where B₂ comes from the same lattice as B₃ and B₃/B₂² is
        then that of the lattice's own discrete particles (exact for parallel squares as the nodes refine as
        1/nodes²), which moved lattices would spoil.
    orientations : {"free", "fixed"}
        "fixed": every particle keeps φ = 0 (parallel particles; ``nphi`` is not used).
    segments : int
        Polyline segments of SeSPs.
    progress : bool
        A progress bar over the orientation pairs of each step, with its ETA, once the work has run 2 s
        (default); False: none.
    memory_limit : int, optional
        Bytes the E₁₂ slices and the E₁₂ and E₁₃ spectra held over φ may take (:func:`held_bytes`); default half the
        available memory. More is refused before any work.

    Returns
    -------
    xarray.Dataset
        ``third_virial_coefficient`` and its ``third_virial_coefficient_error`` (b⁴),
        ``second_virial_coefficient`` ± ``_error`` (b², of particles 1 and 2, from :func:`sesp.excluded_area` for free
        orientations, from the lattice's own count of the φ = 0 slice for fixed ones) and the reduced
        ``reduced_third_virial`` B₃/B₂² with its error; attributes: the lattice (``nodes``, ``spacing``),
        ``nphi``, ``orientations``, ``lattice_error`` and ``phi_error`` (b⁴), ``rtol``, ``converged`` and
        ``seconds`` (all steps).

    Examples
    --------
    >>> from sesp import Polyline
    >>> from sesp.virial import third_virial
    >>> square = Polyline([[-1, -1], [1, -1], [1, 1], [-1, 1], [-1, -1]])
    >>> b = third_virial(square, orientations="fixed", nodes=201, rtol=None)
    >>> round(float(b.reduced_third_virial), 3)  # parallel hard squares: 3/4
    0.75
    """
    rtol = check_rtol(rtol, "B3")
    fixed = check_choice("orientations", orientations, ORIENTATIONS) == "fixed"
    free = {name for name, value in (("nodes", nodes), ("nphi", nphi)) if value is None}
    free -= {"nphi"} if fixed else set()
    settings = {"nodes": START["nodes"] if nodes is None else nodes, "nphi": START["nphi"] if nphi is None else nphi}
    pairs = _three_pairs(particle, second, third, segments)
    t0 = time.perf_counter()
    while True:
        found = _third_virial_at(pairs, settings, shifts, orientations, progress, memory_limit)
        b3, error = float(found.third_virial_coefficient), float(found.third_virial_coefficient_error)
        if rtol is None or error <= rtol * abs(b3):
            converged = True
            break
        step = _next_b3_setting(found, settings, free, shifts, memory_limit)
        if step is None:
            converged = False
            warnings.warn(f"third_virial: rtol {rtol:g} not met: B3 = {b3:.8g} ± {error:.2g} b^4 (relative "
                          f"{error / abs(b3):.2g}) at {settings}; lattice part {found.attrs['lattice_error']:.2g}, "
                          f"orientation part {found.attrs['phi_error']:.2g} b^4; the settings given stay as given "
                          f"(largest refined: {LARGEST})", stacklevel=2)  # fmt: skip
            break
        settings[step] = _raised(step, settings[step])
    seconds = time.perf_counter() - t0
    found.attrs.update(rtol=np.nan if rtol is None else rtol, converged=int(converged), seconds=seconds)
    if fixed:
        return found
    area = excluded_area(particle, second, progress=False)  # the smooth curves': within 1e-5 of the polygons'
    return _with_second_virial(found, float(area.mean_excluded_area) / 2, float(area.mean_excluded_area_error) / 2)


def mixture_third_virial(
    particles,
    fractions=None,
    *,
    rtol: float | None = B3_RTOL,
    b2_rtol: float = RTOL,
    nodes: int | None = None,
    nphi: int | None = None,
    segments: int = DEFAULT_SEGMENTS,
    progress: bool = True,
) -> xr.Dataset:
    """B₃ of a mixture, Σᵢⱼₖ xᵢ xⱼ xₖ B₃,ᵢⱼₖ (b⁴), and B₃/B₂² with the mixture's B₂ (:func:`second_virial`).

    ``particles`` and ``fractions`` as for :func:`second_virial`. B₃,ᵢⱼₖ is the same for every order of i, j, k,
    so one :func:`third_virial` is measured per multiset, to ``rtol`` with ``nodes``, ``nphi`` and ``segments``
    as there; its bar is the same weighted sum of theirs. One species: its B₃, with the B₂ of
    :func:`second_virial` at ``b2_rtol``. Attributes: ``converged`` (1 where every B₃,ᵢⱼₖ met rtol), and for one
    species the ``nodes`` and ``nphi`` it reached."""
    species = list(particles) if isinstance(particles, list | tuple) else [particles]
    b2 = second_virial(species, fractions, rtol=b2_rtol)
    x = b2.fraction.values
    b3, error, converged, found = 0.0, 0.0, True, None
    for triple in itertools.combinations_with_replacement(range(len(species)), 3):
        found = third_virial(*(species[i] for i in triple), rtol=rtol, nodes=nodes, nphi=nphi, segments=segments,
                             progress=progress)  # fmt: skip
        weight = math.prod(x[i] for i in triple) * math.factorial(3)
        weight /= math.prod(math.factorial(triple.count(i)) for i in set(triple))  # the orders of the multiset
        b3 += weight * float(found.third_virial_coefficient)
        error += weight * float(found.third_virial_coefficient_error)
        converged = converged and bool(found.attrs["converged"])
    out = xr.Dataset(
        {
            "third_virial_coefficient": ((), b3, quantity(4, "third virial coefficient B3 of the mixture")),
            "third_virial_coefficient_error": ((), error, quantity(4, "error bar of B3 (lattice + φ)")),
            "fraction": b2.fraction,
        },
        attrs={"converged": int(converged), "rtol": np.nan if rtol is None else rtol},
    )
    if len(species) == 1:
        out.attrs.update(nodes=found.attrs["nodes"], nphi=found.attrs["nphi"])
    b2_value, b2_error = float(b2.second_virial_coefficient), float(b2.second_virial_coefficient_error)
    return _with_second_virial(out, b2_value, b2_error)


def _raised(name: str, value: int) -> int:
    """The next value of a refined setting: nodes to 2·nodes − 1 (every old node kept), nphi by 3/2 to an even
    number (the orientation part falls fast: doubling overshoots)."""
    return 2 * value - 1 if name == "nodes" else 2 * round(0.75 * value)


def _next_b3_setting(found, settings, free, shifts, memory_limit) -> str | None:
    """The setting of the larger part of the error bar (``nodes``: the lattice's, ``nphi``: the orientations'),
    where it is left free, below its largest and fits in memory; else None."""
    name = "nodes" if found.attrs["lattice_error"] >= found.attrs["phi_error"] else "nphi"
    raised = {**settings, name: _raised(name, settings[name])}
    if name not in free or raised[name] > LARGEST[name]:
        return None
    try:
        _checked(raised["nodes"], raised["nphi"], shifts, found.attrs["orientations"], memory_limit)
    except MemoryError:
        return None
    return name


def _third_virial_at(pairs, settings, shifts, orientations, progress, memory_limit) -> xr.Dataset:
    """B₃ at the given lattice and orientations; for fixed orientations with B₂ from the φ = 0 slice of the
    same lattice."""
    nodes, nphi, shifts = _checked(settings["nodes"], settings["nphi"], shifts, orientations, memory_limit)
    fixed = orientations == "fixed"
    xs = _lattice(max(p.reach for p in pairs), nodes)
    h = float(xs[1] - xs[0])
    counts = _triple_counts(pairs, xs, nphi, shifts, progress)
    b3, lattice_error, phi_error = _b3_and_errors(counts, h, fixed)
    found = xr.Dataset(
        {
            "third_virial_coefficient": ((), b3, quantity(4, "third virial coefficient B3")),
            "third_virial_coefficient_error": ((), lattice_error + phi_error,
                                               quantity(4, "error bar of B3 (lattice + φ)")),
        },
        attrs={"nodes": len(xs), "spacing": h, "nphi": nphi, "orientations": orientations,
               "lattice_error": lattice_error, "phi_error": phi_error},
    )  # fmt: skip
    if not fixed:
        return found
    e12 = [_overlaps(pairs[0].vertices1, pairs[0].vertices2, 0.0, 0.0, xs, pairs[0], move)
           for move in _moves(shifts, h)]  # fmt: skip
    return _with_second_virial(found, 0.5 * float(np.mean([e.sum() for e in e12])) * h * h, 0.0)  # the lattice's


def _with_second_virial(found: xr.Dataset, b2: float, b2_error: float) -> xr.Dataset:
    """``found`` with B₂ (b²) and the reduced B₃/B₂² with its error."""
    b3, error = float(found.third_virial_coefficient), float(found.third_virial_coefficient_error)
    ratio = b3 / b2**2
    ratio_error = ratio * (error / abs(b3) + 2 * b2_error / b2)
    out = found.assign(
        second_virial_coefficient=((), b2, quantity(2, "second virial coefficient B2")),
        second_virial_coefficient_error=((), b2_error, quantity(2, "error bar of B2")),
        reduced_third_virial=((), ratio, {"units": "1", "long_name": "B3 / B2^2"}),
        reduced_third_virial_error=((), abs(ratio_error), {"units": "1", "long_name": "error bar of B3 / B2^2"}),
    )
    return link_errors(out)


def _checked(nodes, nphi, shifts, orientations, memory_limit) -> tuple:
    """(nodes, nphi, shifts) checked, with the defaults of the orientations (``shifts`` None: 4 for free
    orientations, 1 for fixed ones, where nphi is 1); ``MemoryError`` if they would not fit in
    ``memory_limit``."""
    check_choice("orientations", orientations, ORIENTATIONS)
    nodes = check_count("nodes", nodes, 9, 4097)
    if nodes % 2 == 0:
        raise ValueError(f"nodes must be odd (a node at the origin), got {nodes}")
    fixed = orientations == "fixed"
    shifts = check_count("shifts", (1 if fixed else 4) if shifts is None else shifts, 1, 64)
    nphi = 1 if fixed else check_count("nphi", nphi, 2, 1024)
    if not fixed and nphi % 2:
        raise ValueError(f"nphi must be even (every other orientation is the coarser rule), got {nphi}")
    check_held_bytes(nodes, nphi, shifts, memory_limit)
    return nodes, nphi, shifts


def _moves(shifts: int, h: float) -> np.ndarray:
    """(shifts, 2): the low-discrepancy moves (b) of the lattices of particles 2 and 3 (their difference's
    lattice is unmoved)."""
    return lattice_shifts(2 * shifts)[:shifts] * h


def _triple_counts(pairs, xs, nphi: int, shifts: int, progress: bool) -> np.ndarray:
    """(shifts, nphi, nphi, 2): Σ_{r₂} E₁₂ Σ_{r₃} E₁₃ E₂₃ in node counts per shift and orientations (φ₂, φ₃),
    on the lattice ``xs`` and on its sublattice of every other node. Orientation pairs are shared among
    threads (numba's thread count); each writes its own entries, so the counts do not depend on it."""
    p12, p13, p23 = pairs
    phi = 2 * np.pi * np.arange(nphi) / nphi
    moves = _moves(shifts, float(xs[1] - xs[0]))
    fine, coarse = _Correlator(len(xs)), _Correlator(len(xs[::2]))

    def slice_and_spectra(pair, move, angle):
        e = _overlaps(pair.vertices1, pair.vertices2, 0.0, angle, xs, pair, move)
        return e, fine.spectrum(e), coarse.spectrum(e[::2, ::2])

    with ThreadPoolExecutor(numba.get_num_threads()) as pool:
        e12 = [list(pool.map(lambda a, m=m: slice_and_spectra(p12, m, a), phi)) for m in moves]
        e13 = [list(pool.map(lambda a, m=m: slice_and_spectra(p13, m, a), phi)) for m in moves]
        symmetric = p23.identical
        todo = [(j, k) for j in range(nphi) for k in range(nphi) if not (symmetric and k < j)]
        counts = np.zeros((shifts, nphi, nphi, 2))

        def one_pair(jk):
            j, k = jk
            e23 = _overlaps(p23.vertices1, p23.vertices2, phi[j], phi[k], xs, p23)
            f23 = (fine.spectrum(e23), coarse.spectrum(e23[::2, ::2]))
            for m in range(shifts):
                e, s12_fine, s12_coarse = e12[m][j]
                counts[m, j, k, 0] = fine.triple(e, s12_fine, e13[m][k][1], f23[0])
                counts[m, j, k, 1] = coarse.triple(e[::2, ::2], s12_coarse, e13[m][k][2], f23[1])
            if symmetric:
                counts[:, k, j] = counts[:, j, k]

        with progress_bar(len(todo), progress, "B3 orientation pairs", unit="pair") as bar:
            for _ in pool.map(one_pair, todo):
                bar.update(1)
    return counts


def _b3_and_errors(counts, h: float, fixed: bool) -> tuple:
    """(B₃, lattice error, φ error), b⁴, from the triple counts on lattices of spacing ``h`` (b): the mean over
    the shifts; the lattice part the larger of twice the standard error over the shifts and the change from
    the sublattice; the orientation part the change from every other orientation."""
    shifts = counts.shape[0]
    per_shift = counts[..., 0].mean(axis=(1, 2)) * h**4 / 3
    b3 = float(per_shift.mean())
    coarse_b3 = float(counts[..., 1].mean()) * (2 * h) ** 4 / 3
    spread = float(per_shift.std(ddof=1)) / math.sqrt(shifts) if shifts > 1 else 0.0
    lattice_error = max(2 * spread, abs(b3 - coarse_b3))  # first order: flat sides along the lattice
    phi_error = abs(b3 - float(counts[:, ::2, ::2, 0].mean()) * h**4 / 3) if not fixed else 0.0
    return b3, lattice_error, phi_error


def _three_pairs(particle, second, third, segments: int) -> tuple:
    """The pairs (1, 2), (1, 3) and (2, 3) of three particles, ``second`` and ``third`` defaulting to
    ``particle``."""
    second = particle if second is None else second
    third = particle if third is None else third
    return tuple(as_pair(a, b, segments) for a, b in ((particle, second), (particle, third), (second, third)))


def held_bytes(nodes: int, nphi: int, shifts: int) -> int:
    """Bytes :func:`third_virial` holds through its loop over orientation pairs: per shift and orientation,
    E₁₂ (float, nodes²) and the spectra of E₁₂ and E₁₃ on the lattice and its sublattice (complex,
    2n × (n + 1) each)."""
    half = (nodes + 1) // 2
    spectra = 16 * (2 * nodes * (nodes + 1) + 2 * half * (half + 1))
    return shifts * nphi * (8 * nodes * nodes + 2 * spectra)


def check_held_bytes(nodes: int, nphi: int, shifts: int, limit: int | None = None) -> None:
    """Raise ``MemoryError`` naming the settings if :func:`held_bytes` exceeds ``limit`` (default half the
    available memory)."""
    limit = available_memory() // 2 if limit is None else int(limit)
    held = held_bytes(nodes, nphi, shifts)
    if held > limit:
        raise MemoryError(
            f"third_virial with nodes={nodes}, nphi={nphi}, shifts={shifts} holds {held / 2**30:.2f} GiB, over the"
            f" memory limit of {limit / 2**30:.2f} GiB: use fewer nodes or orientations"
        )


def third_virial_monte_carlo(
    particle, second=None, third=None, *, samples: int = 1_000_000, seed=None, segments: int = DEFAULT_SEGMENTS
):
    """B₃ of one species, or B₃,ᵢⱼₖ of three, by Monte Carlo over (r₂, φ₂, r₃, φ₃), with its standard error
    (b⁴): the independent check of :func:`third_virial`, on sesp's state-by-state overlap test (no lattice).

    r₂ is uniform in the square of half-width r₁ + r₂ (nothing farther overlaps particle 1), r₃ in that of
    half-width r₁ + r₃, φ₂ and φ₃ uniform; the estimate is (1/3)·(2(r₁ + r₂))²·(2(r₁ + r₃))² times the mean
    of E₁₂ E₁₃ E₂₃, E₂₃ decided in particle 2's frame. ``second`` and ``third`` default to ``particle``.
    """
    samples = check_count("samples", samples, 1, 1 << 34)
    p12, p13, p23 = _three_pairs(particle, second, third, segments)
    rng = np.random.default_rng(seed)
    half2, half3 = p12.reach, p13.reach
    t0 = time.perf_counter()
    total, total2, done = 0.0, 0.0, 0
    while done < samples:
        m = min(1 << 20, samples - done)
        x2, y2 = rng.uniform(-half2, half2, size=(2, m))
        x3, y3 = rng.uniform(-half3, half3, size=(2, m))
        phi2, phi3 = rng.uniform(0.0, 2 * math.pi, size=(2, m))
        hit = overlaps(p12, None, x2, y2, phi2) & overlaps(p13, None, x3, y3, phi3)
        c, s = np.cos(phi2[hit]), np.sin(phi2[hit])
        dx, dy = x3[hit] - x2[hit], y3[hit] - y2[hit]
        both = np.zeros(m, dtype=bool)
        both[hit] = overlaps(p23, None, c * dx + s * dy, -s * dx + c * dy, phi3[hit] - phi2[hit])
        total += both.sum()
        total2 += both.sum()  # 0/1 values: the sum of squares is the sum
        done += m
    mean = total / samples
    error = math.sqrt(max(total2 / samples - mean**2, 0.0) / max(samples - 1, 1))
    scale = (2 * half2) ** 2 * (2 * half3) ** 2 / 3
    return link_errors(
        xr.Dataset(
            {
                "third_virial_coefficient": ((), mean * scale, quantity(4, "third virial coefficient B3")),
                "third_virial_coefficient_error": ((), error * scale, quantity(4, "standard error of B3")),
            },
            attrs={"samples": samples, "seconds": time.perf_counter() - t0},
        )
    )
