"""The proposal as a section of an analysis.

:func:`proposal_part` proposes counterweights and balance shafts for an analysed engine
(:func:`balance.core.balancing.propose`) and forms the residual: the free forces with
every proposed mass added.  It is a section (:mod:`balance.core.sections`); its outputs are
:data:`OUTPUTS`.  The balance-factor study is :mod:`balance.core.factor_study`.
"""

from __future__ import annotations

from collections.abc import Iterable, Sequence
from dataclasses import dataclass, replace
from typing import Any

import numpy as np
from numpy.typing import NDArray

from balance.core.analysis import compute_phasors
from balance.core.balance_factor import BalanceFactor, FactorEquivalents
from balance.core.balancing import Proposal, propose
from balance.core.catalogue import Output
from balance.core.counterweights import counterweight_moment_z, proposal_phasors, propose_geared
from balance.core.engine import Engine, ShaftPosition
from balance.core.phasors import Phasors, cancel_to_zero, phase_deg, safe_ratio
from balance.core.proposal_notes import cancel_roll_notes, factor_note, orders_left
from balance.core.result import FreeForces, Result
from balance.core.shafts import shaft_roll_phasors
from balance.core.speed import speed_squared

__all__ = [
    "OUTPUTS",
    "ProposalResult",
    "balance_engine",
    "proposal_part",
    "residual",
]

ComplexArray = NDArray[np.complex128]
FloatArray = NDArray[np.float64]


@dataclass(frozen=True)
class ProposalResult:
    """A balancing proposal and what remains with it.

    Attributes
    ----------
    proposal : Proposal
        The counterweights and balance shafts (:class:`balance.core.balancing.Proposal`).
    residual : Phasors
        Per order of the analysis: reciprocating + rotating + counterweights + shafts
        [N, N m], and the roll (inertia, whole orders) with the shafts' roll added.
    residual_moment_z : ndarray of complex or None
        An engine with several crank axes: per order of the residual, the moment about the
        frame's ``z`` axis of the free forces on their axes with the counterweights' [N m]
        (roll convention); None for one crank.
    residual_roll : ndarray of complex or None
        The roll as the analysis reports it (per :attr:`Result.roll_orders`, with gas
        forces where the engine has them) with the shafts' roll added [N m]; None
        without the roll.
    left : tuple of int
        The orders the proposal was asked to cancel whose residual force or moment is not
        zero (a balance factor's forward first order, a sense without a shaft of the
        layout's ``shafts``); the notes say why.
    """

    proposal: Proposal
    residual: Phasors
    residual_roll: ComplexArray | None
    left: tuple[int, ...] = ()
    residual_moment_z: ComplexArray | None = None


def _factor(value: float | BalanceFactor | None, of: str | None) -> float | BalanceFactor | None:
    """A balance factor with its convention: ``of`` given names the convention of a bare
    ``value`` (each cylinder's reciprocating mass without it)."""
    if value is None or of is None or isinstance(value, BalanceFactor):
        return value
    return BalanceFactor(float(value), of)


def balance_engine(
    layout: Engine,
    free: FreeForces,
    *,
    cancel: Iterable[int] | None = None,
    strategy: str | None = None,
    balance_factor: float | BalanceFactor | None = None,
    counterweight_radius: float | None = None,
    cancel_roll: bool = False,
    fixed_shafts: Sequence[ShaftPosition] | None = None,
    balance_factor_of: str | None = None,
) -> ProposalResult:
    """Propose counterweights and shafts for an analysed layout and form the residual.

    Parameters
    ----------
    layout : Engine
        The engine.
    free : FreeForces
        Its free forces (:func:`balance.core.analysis.compute_phasors`); the orders to
        cancel are computed again with the same model where they are not among them.
    cancel, strategy, balance_factor, counterweight_radius, cancel_roll, fixed_shafts
        Proposal settings (:func:`balance.core.balancing.propose`).  Those not given here
        come from the layout's ``balance:`` section (``fixed_shafts``: its ``shafts``),
        then from the defaults of :func:`balance.core.balancing.propose` (orders 1 and 2,
        two-plane counterweights at the crank ends, counterweight radius = crank radius,
        shafts where they are needed at their default places).
    balance_factor_of : {'each-cylinder', 'one-cylinder'}, optional
        The convention of a float ``balance_factor`` (:mod:`balance.core.balance_factor`);
        default each cylinder's reciprocating mass.

    Returns
    -------
    ProposalResult
        The proposal, with the notes computed from the residual
        (:mod:`balance.core.proposal_notes`), the residual per order of ``free``
        (:func:`residual`), its roll (inertia, whole orders; :func:`proposal_part` puts the
        roll with gas forces in its place) and the orders left.
    """
    balance_factor = _factor(balance_factor, balance_factor_of)
    settings = layout.balance
    if cancel is None and settings is not None and settings.orders is not None:
        cancel = settings.orders
    wanted = sorted({int(k) for k in (cancel if cancel is not None else (1, 2))})
    if strategy is None:
        strategy = settings.strategy if settings is not None else "two-plane"
    if balance_factor is None and settings is not None:
        balance_factor = settings.balance_factor
    if counterweight_radius is None and settings is not None:
        counterweight_radius = settings.counterweight_radius
    if fixed_shafts is None and settings is not None:
        fixed_shafts = settings.shafts
    # the phasors of the orders to cancel (computed again only if not already there)
    p = free.phasors
    needed = np.asarray(wanted, dtype=np.intp)
    source = free
    if not (set(wanted) <= set(p.orders.tolist()) and p.has("moment") and p.roll is not None):
        source = compute_phasors(
            layout,
            needed,
            model=free.model.name,
            terms=free.model.terms,
            samples=free.model.samples or None,
        )
    picked = source.phasors.at(needed)
    assert picked.moment_forward is not None and picked.moment_backward is not None
    assert picked.roll is not None
    first_order = (
        source.coefficients[:, int(np.searchsorted(source.phasors.orders, 1))]
        if 1 in wanted
        else np.ones(layout.n_cylinders, dtype=np.complex128)
    )
    pins = None
    if 1 in wanted and source.link_pins is not None:
        if layout.geared:  # forward and backward apart: counterweights turn either way
            at = int(np.searchsorted(source.link_pins.orders, 1))
            pins = (source.link_pins.force_forward[:, at], source.link_pins.force_backward[:, at])
        else:
            first_order = first_order + _link_pin_first_order(layout, source.link_pins)
    if layout.geared:
        proposal = propose_geared(
            layout,
            first_order,
            picked,
            cancel=wanted,
            strategy=strategy,
            balance_factor=balance_factor,
            counterweight_radius=counterweight_radius,
            fixed_shafts=fixed_shafts,
            cancel_roll=cancel_roll,
            link_pins=pins,
        )
    else:
        proposal = propose(
            layout,
            first_order,
            picked.force_forward,
            picked.force_backward,
            picked.moment_forward,
            picked.moment_backward,
            needed,
            cancel=wanted,
            strategy=strategy,
            balance_factor=balance_factor,
            counterweight_radius=counterweight_radius,
            fixed_shafts=fixed_shafts,
            cancel_roll=cancel_roll,
            roll=picked.roll,
        )
    after = residual(layout, proposal, p)
    # the notes speak of the orders to cancel: the residual's own entries where they are
    # among its orders (each order's sum is formed and cleaned on its own), read beside the
    # free forces of the same orders
    pistons, kept = (p, after) if source is free else (picked, residual(layout, proposal, picked))
    backward = layout.geared and bool(np.any(layout.axis_table().rotation < 0))
    head = [note] if (note := factor_note(proposal, pistons, kept, backward)) else []
    tail = cancel_roll_notes(proposal, kept)
    if head or tail:
        proposal = replace(proposal, notes=(*head, *proposal.notes, *tail))
    return ProposalResult(proposal, after, after.roll, orders_left(proposal, kept))


def residual(layout: Engine, proposal: Proposal, p: Phasors) -> Phasors:
    """The free phasors with the proposed masses added, each sum cleaned of rounding
    noise against the terms that meet in it (:func:`balance.core.phasors.cancel_to_zero`).

    Parameters
    ----------
    layout : Engine
        The engine.
    proposal : Proposal
        Its proposal (:func:`balance_engine`).
    p : Phasors
        Its free forces, moments and roll [N, N m].

    Returns
    -------
    Phasors
        Reciprocating + rotating + every proposed mass, per order of ``p``; the roll with
        the shafts' roll.
    """
    total = p.free() + proposal_phasors(proposal, layout, p.orders)
    w2 = float(speed_squared(layout.speed))
    lever = np.abs(layout.z - layout.reference_z)
    # scale of the terms that meet in each residual sum, for the zero-by-symmetry threshold
    force_scale = float(
        np.sum((layout.reciprocating_mass + layout.rotating_mass) * layout.crank_radius) * w2
    )
    force_scale += sum(abs(c.unbalance) for c in proposal.counterweights) * w2
    force_scale += sum(abs(u) * s.speed_ratio**2 for s in proposal.shafts for _, u in s.planes) * w2
    span = float(
        max(
            lever.max(),
            *(abs(c.z - layout.reference_z) for c in proposal.counterweights),
            *(abs(z - layout.reference_z) for s in proposal.shafts for z, _ in s.planes),
            0.0,
        )
    )
    n_terms = 2 * layout.n_cylinders + len(proposal.counterweights) + 2 * len(proposal.shafts)

    def clean(values: Any, scale: float) -> ComplexArray:
        return cancel_to_zero(values, scale, n_terms)

    roll_scale = float(np.sum(layout.reciprocating_mass * layout.crank_radius**2) * w2)
    roll_scale += float(np.sum(np.abs(layout.conrod_inertia_correction)) * w2)
    roll_scale += sum(  # each shaft's own roll: a placed pair's two cancel each other
        float(np.abs(shaft_roll_phasors([s], layout.speed, [abs(s.speed_ratio)])[0]))
        for s in proposal.shafts
    )

    def cleaned(values: Any, scale: float) -> Any:
        return None if values is None else clean(values, scale)

    return total.replaced(
        force_forward=clean(total.force_forward, force_scale),
        force_backward=clean(total.force_backward, force_scale),
        moment_forward=cleaned(total.moment_forward, force_scale * span),
        moment_backward=cleaned(total.moment_backward, force_scale * span),
        roll=cleaned(total.roll, roll_scale),
    )


def _link_pin_first_order(layout: Engine, pins: Phasors) -> ComplexArray:
    r"""What each link pin's relative motion adds to its cylinder's :math:`G_1` as the
    counterweights see it: :math:`2P^{+}_1/(m_{rec} r\omega^2 e^{i\varphi})`, so that the
    counterweights' targets (each cylinder's unbalance, :mod:`balance.core.balancing`) hold the
    whole forward first order of every cylinder."""
    at = int(np.searchsorted(pins.orders, 1))
    carrier = (
        layout.reciprocating_mass
        * layout.crank_radius
        * speed_squared(layout.speed)
        * np.exp(1j * layout.throw)
    )
    return np.asarray(2.0 * pins.force_forward[:, at] / carrier, dtype=np.complex128)


def _with_shafts_roll(result: Result, residual: Phasors) -> ComplexArray:
    """The reported roll with the proposed shafts' roll added.

    Without gas forces the roll is the inertia roll of whole orders and this is the
    residual's.  With them (half orders for a four-stroke), the shafts' roll, which has
    whole orders only, is added to the orders it has.
    """
    assert result.roll is not None and residual.roll is not None
    if result.part("torque") is None:
        return residual.roll
    assert result.phasors.roll is not None
    ks = result.roll_orders
    roll = result.roll
    out = roll.copy()
    shafts = residual.roll - result.phasors.roll  # the shafts' roll, whole orders only
    for j, k in enumerate(result.phasors.orders):
        at = np.flatnonzero(np.isclose(ks, float(k)))
        if at.size:
            out[at[0]] += shafts[j]
    scale = float(np.sum(np.abs(roll)) + np.sum(np.abs(shafts)))
    return cancel_to_zero(out, scale, 64)


def proposal_part(
    engine: Engine,
    request: Any,
    result: Result,
    *,
    cancel: Iterable[int] | None = None,
    strategy: str | None = None,
    balance_factor: float | None = None,
    counterweight_radius: float | None = None,
    cancel_roll: bool = False,
    balance_factor_of: str | None = None,
) -> Result:
    """The ``proposal`` section: the proposal and the residual (:class:`ProposalResult`).

    A proposal needs the moments and the roll; without them the result is returned as it
    is.

    Parameters
    ----------
    engine : Engine
        The analysed engine.
    request : Request
        The request.
    result : Result
        The result so far (its free forces, and the roll with gas forces when the torque
        section has run).
    cancel, strategy, balance_factor, counterweight_radius, cancel_roll, balance_factor_of
        Proposal settings, as :func:`balance_engine` (orders to cancel; ``'two-plane'`` or
        ``'per-throw'``; a fraction [1]; a radius [m]; place the shafts to cancel the roll;
        the convention of ``balance_factor``, ``'each-cylinder'`` or ``'one-cylinder'``).

    Returns
    -------
    Result
        ``result`` with the ``proposal`` part added.
    """
    if not result.has_moments or result.roll is None:
        return result
    proposed = balance_engine(
        engine,
        FreeForces(result.phasors, result.coefficients, result.model, result.link_pins),
        cancel=cancel,
        strategy=strategy,
        balance_factor=balance_factor,
        counterweight_radius=counterweight_radius,
        cancel_roll=cancel_roll,
        balance_factor_of=balance_factor_of,
    )
    roll = _with_shafts_roll(result, proposed.residual)
    part = proposed if roll is proposed.residual_roll else replace(proposed, residual_roll=roll)
    if engine.geared and result.shafts is not None:
        part = replace(part, residual_moment_z=_moment_z_with(engine, result, part.proposal))
    return result.with_part("proposal", part)


def _moment_z_with(engine: Engine, result: Result, proposal: Proposal) -> ComplexArray:
    """The moment about ``z`` per order of the analysis with the counterweights' added
    (docs/several-crankshafts.md, "The moment about z")."""
    engine_z = np.asarray(result.shafts.moment_z, dtype=np.complex128)
    w2 = float(speed_squared(engine.speed))
    terms = [counterweight_moment_z(cw, w2) for cw in proposal.counterweights]
    first = np.asarray(result.phasors.orders) == 1
    added = np.where(first, sum(terms, 0j), 0j)
    scale = np.abs(engine_z) + np.where(first, sum(abs(t) for t in terms), 0.0)
    return cancel_to_zero(engine_z + added, scale, len(terms) + 2 * engine.n_cylinders)


# --------------------------------------------------------------------------- outputs


def _proposal(result: Any) -> ProposalResult:
    part: ProposalResult = result.part("proposal")
    return part


def _residual_roll(result: Any) -> ComplexArray:
    roll = _proposal(result).residual_roll
    assert roll is not None  # a proposal is made with the roll
    return roll


def _planes(result: Any) -> tuple[FloatArray, ComplexArray]:
    """Each shaft's planes as arrays (shafts, planes): z [m] and unbalance [kg m], NaN
    where a shaft has fewer planes than the most."""
    shafts = _proposal(result).proposal.shafts
    n_planes = max((len(s.planes) for s in shafts), default=0)
    plane_z = np.full((len(shafts), n_planes), np.nan)
    plane_u = np.full((len(shafts), n_planes), np.nan + 0j)
    for i, shaft in enumerate(shafts):
        for j, (z, u) in enumerate(shaft.planes):
            plane_z[i, j] = z
            plane_u[i, j] = u
    return plane_z, plane_u


def _counterweights(attribute: str) -> Any:
    return lambda r: [getattr(c, attribute) for c in _proposal(r).proposal.counterweights]


def _shafts(attribute: str) -> Any:
    return lambda r: [getattr(s, attribute) for s in _proposal(r).proposal.shafts]


def _gas_and(result: Any) -> str:
    return "gas forces and " if result.part("torque") is not None else ""


def _residual_outputs(quantity: str) -> tuple[Output, ...]:
    unit = "N" if quantity == "force" else "N m"
    per = "m_rec r omega^2" if quantity == "force" else "m_rec r omega^2 a"

    def peak(r: Any) -> Any:
        return _proposal(r).residual.peak(quantity)  # type: ignore[arg-type]

    def reference(r: Any) -> float:
        return float(r.reference_force if quantity == "force" else r.reference_moment)

    return (
        Output(
            f"residual_{quantity}_magnitude",
            ("order", "rotation"),
            unit,
            f"residual {quantity} phasor magnitude with the proposal",
            lambda r: _proposal(r).residual.magnitude(quantity),  # type: ignore[arg-type]
        ),
        Output(
            f"residual_{quantity}_phase",
            ("order", "rotation"),
            "deg",
            f"residual {quantity} phasor phase at crank angle 0",
            lambda r: _proposal(r).residual.phase(quantity),  # type: ignore[arg-type]
        ),
        Output(
            f"residual_{quantity}_peak",
            ("order",),
            unit,
            f"peak residual {quantity} (reciprocating + rotating + proposal)",
            peak,
        ),
        Output(
            f"residual_{quantity}_peak_normalised",
            ("order",),
            "1",
            f"peak residual {quantity} per {per}",
            lambda r: safe_ratio(peak(r), reference(r)),
        ),
    )


def _has_moment_z(result: Any) -> bool:
    return _proposal(result).residual_moment_z is not None


def _residual_moment_z(result: Any) -> Any:
    value = _proposal(result).residual_moment_z
    assert value is not None
    return np.abs(value)


def _factor_of(result: Any) -> FactorEquivalents | None:
    return _proposal(result).proposal.factor


def _equivalents(result: Any) -> FactorEquivalents:
    factor = _factor_of(result)
    assert factor is not None
    return factor


def _attr(name: str, get: Any, **options: Any) -> Output:
    return Output(name, (), "", name, get, kind="attr", **options)


#: The outputs of the ``proposal`` section.
OUTPUTS: tuple[Output, ...] = (
    Output(
        "counterweight_z",
        ("counterweight",),
        "m",
        "axial plane of the proposed counterweight",
        _counterweights("z"),
    ),
    Output(
        "counterweight_mass",
        ("counterweight",),
        "kg",
        "counterweight mass at counterweight_radius",
        _counterweights("mass"),
    ),
    Output(
        "counterweight_radius",
        ("counterweight",),
        "m",
        "radius of the counterweight's centre of gravity",
        _counterweights("radius"),
    ),
    Output(
        "counterweight_angle",
        ("counterweight",),
        "deg",
        "counterweight angle at crank angle 0, turning with the crank",
        _counterweights("angle_deg"),
    ),
    Output(
        "counterweight_unbalance",
        ("counterweight",),
        "kg m",
        "counterweight mass times radius",
        lambda r: np.abs(
            np.array(
                [c.unbalance for c in _proposal(r).proposal.counterweights], dtype=np.complex128
            )
        ),
    ),
    Output(
        "shaft_speed_ratio",
        ("shaft",),
        "1",
        "balance shaft speed over crank speed (negative: against it)",
        _shafts("speed_ratio"),
    ),
    Output("shaft_x", ("shaft",), "m", "balance shaft axis, x", _shafts("x")),
    Output("shaft_y", ("shaft",), "m", "balance shaft axis, y", _shafts("y")),
    Output(
        "shaft_plane_z",
        ("shaft", "shaft_plane"),
        "m",
        "axial plane of the shaft's eccentric mass",
        lambda r: _planes(r)[0],
    ),
    Output(
        "shaft_plane_unbalance",
        ("shaft", "shaft_plane"),
        "kg m",
        "eccentric mass times eccentricity",
        lambda r: np.abs(_planes(r)[1]),
    ),
    Output(
        "shaft_plane_angle",
        ("shaft", "shaft_plane"),
        "deg",
        "eccentric angle at crank angle 0 (it sits at angle + speed_ratio * theta)",
        lambda r: phase_deg(_planes(r)[1]),
    ),
    *_residual_outputs("force"),
    *_residual_outputs("moment"),
    Output(
        "residual_moment_z_peak",
        ("order",),
        "N m",
        "peak residual moment about the frame's z axis of the crankshafts' free forces and "
        "counterweights (several crankshafts)",
        _residual_moment_z,
        when=_has_moment_z,
    ),
    Output(
        "residual_roll_amplitude",
        ("roll_order",),
        "N m",
        lambda r: f"roll torque amplitude with {_gas_and(r)}the proposed shafts",
        lambda r: np.abs(_residual_roll(r)),
    ),
    Output(
        "residual_roll_phase",
        ("roll_order",),
        "deg",
        lambda r: f"roll torque phase with {_gas_and(r)}the proposed shafts",
        lambda r: phase_deg(_residual_roll(r)),
    ),
    _attr("proposal_strategy", lambda r: _proposal(r).proposal.strategy),
    _attr(
        "proposal_orders",
        lambda r: np.asarray(_proposal(r).proposal.orders, dtype=np.int64),
    ),
    _attr("proposal_cancel_roll", lambda r: int(_proposal(r).proposal.cancel_roll)),
    _attr("proposal_notes", lambda r: "; ".join(_proposal(r).proposal.notes)),
    _attr(
        "proposal_orders_left",  # present only when an order to cancel is left in part
        lambda r: np.asarray(_proposal(r).left, dtype=np.int64),
        when=lambda r: bool(_proposal(r).left),
    ),
    _attr(
        "proposal_balance_factor",  # a number, present only when a balance factor was given
        lambda r: float(_proposal(r).proposal.balance_factor or 0.0),
        when=lambda r: _proposal(r).proposal.balance_factor is not None,
    ),
    _attr(
        "proposal_balance_factor_one_cylinder",  # the same as a share of one cylinder's
        lambda r: float(_equivalents(r).one_cylinder or 0.0),
        when=lambda r: _factor_of(r) is not None and _equivalents(r).one_cylinder is not None,
    ),
    _attr(
        "proposal_balance_factor_of",  # the convention the factor was given in
        lambda r: _equivalents(r).given.of,
        when=lambda r: _factor_of(r) is not None,
    ),
    _attr(
        "proposal_balance_factor_convention",  # the factor given, in words, in both
        lambda r: _equivalents(r).describe(),
        when=lambda r: _factor_of(r) is not None,
    ),
)
