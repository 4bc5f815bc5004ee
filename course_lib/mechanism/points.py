"""The declared points along a motion: their coordinates (``joints``) and their velocities and
accelerations (``point_motion``), from the points' declaration differentiated in time.

One room of :class:`~course_lib.mechanism.Mechanism`, which is all of them together.
"""

from __future__ import annotations

from collections.abc import Mapping

import numpy as np

from ..errors import (
    InvalidArgumentError,
    InvalidGeometryError,
    require_finite,
)
from ..motion import Motion
from .closed_forms import RESIDUAL
from .compiled import _finite_rows, _vector
from .declaration import _derived, _keyed
from .singular import NEAR_SINGULAR


class Points:
    """The declared points along a motion: coordinates, velocities, accelerations."""

    @_derived
    def _point_fn(self):
        return self._compile([c for xy in self.points.values() for c in xy], self.unknowns, self.inputs)

    @_derived
    def _point_rate_fn(self):
        """(q, q̇, q̈, u, u̇, ü) → each point's velocity and acceleration, its declaration differentiated."""
        terms = []
        for point in self.points.values():
            terms += [entry for derivative in self._in_time(point) for entry in derivative]
        q, u = self.unknowns, self.inputs
        return self._compile(terms, q, self._rates_of(q, 1), self._rates_of(q, 2), u, self._rates_of(u, 1),
                             self._rates_of(u, 2))

    def _check_rigid(self, q: np.ndarray, u: np.ndarray) -> None:
        """Every declared link (and every side of a plate) keeps its length along the motion, else the named
        error: its length's rate, d|PQ|/dt = (P − Q)·(Ṗ − Q̇)/|PQ|, is checked at up to four regular
        instants of ``q``, ``u`` (solved instants; ``solve`` gives 257 spread over the motion) for each input
        turning at unit rate — the points' declaration differentiated by the core.
        Checked once per declaration (a point written with the wrong unknown stretches its links)."""
        with np.errstate(all="ignore"):
            J = self._J(q, u)
            regular = np.flatnonzero(self._smallest(J) >= NEAR_SINGULAR)  # rates well determined
        if not len(regular):
            return
        self._numeric["rigid"] = True
        pick = regular[np.linspace(0, len(regular) - 1, min(4, len(regular))).astype(int)]
        q, u = q[pick], u[pick]
        n, m = len(self.unknowns), len(self.inputs)
        pairs = dict(self.links.named())
        for plate, corners in self.plates.items():
            sides = zip(corners, corners[1:] + corners[:1], strict=True)
            pairs |= {f"plate {plate!r} side {a}{b}": (a, b) for a, b in sides}
        names = list(self.points)
        for j, input_ in enumerate(self.inputs):
            u_rate = np.zeros((len(u), m))
            u_rate[:, j] = 1.0
            q_rate, _, _ = self.unknown_rates(q, u, u_rate)
            zeros_n, zeros_m = np.zeros((len(u), n)), np.zeros((len(u), m))
            terms = self._point_rate_fn(self._values, q, q_rate, zeros_n, u, u_rate, zeros_m)
            xy = self._point_fn(self._values, q, u)
            where = {name: (_vector(xy, 2 * k, 2), _vector(terms, 4 * k, 2)) for k, name in enumerate(names)}
            speeds = np.max([np.linalg.norm(v, axis=-1) for _, v in where.values()], axis=0)
            sizes = np.max([np.linalg.norm(p - where[names[0]][0], axis=-1) for p, _ in where.values()],
                           axis=0)
            for link, (a, b) in pairs.items():
                (pa, va), (pb, vb) = where[a], where[b]
                gap = np.linalg.norm(pa - pb, axis=-1)
                rate = np.einsum("ij,ij->i", pa - pb, va - vb) / np.where(gap > 0, gap, 1.0)
                bad = np.abs(rate) > 1e-7 * (speeds + sizes)
                if bad.any():
                    k = int(np.argmax(bad))
                    if self._units is not None:  # a twin's lengths (see .scaling): in the declaration's units
                        gap, rate = gap * self._units.length, rate * self._units.length / self._units.u[j]
                    raise InvalidGeometryError(
                        f"links: {link} ({a}–{b}) changes length as the mechanism moves: |{a}{b}| = "
                        f"{gap[k]:.6g} at {self._where(u, k)}, changing at {rate[k]:.3g} per unit of "
                        f"{input_.name}; a link keeps its length, so points[{a!r}] or points[{b!r}] is not "
                        f"where the loops put it (an unknown written for another?)")

    def point_motion(self, motion: Motion, rates: Mapping | None = None, accelerations: Mapping | None = None
                     ) -> dict[str, tuple[np.ndarray, np.ndarray, np.ndarray]]:
        """Position, velocity and acceleration (each (..., 2), SI) of every declared point along ``motion``,
        from the point's declaration differentiated in time — ω k̂ × r and α k̂ × r − ω² r, Coriolis
        terms included, without writing any of them by hand.  The inputs' ``rates`` and ``accelerations``
        are the ones the motion was solved with: read from it when left out (the loops' rate equations
        solved for them), refused by name when given otherwise.

        >>> th, x = sp.symbols("theta x")
        >>> A = sp.Matrix([sp.cos(th), sp.sin(th)])
        >>> crank = Mechanism([x - sp.cos(th)], [x], [th], points={"O": sp.zeros(2, 1), "A": A},
        ...                   links=[("O", "A")])
        >>> turning = crank.solve({th: 0.0}, rates={th: 2.0}, guess={x: 1.0})
        >>> [v.round(12).tolist() for v in crank.point_motion(turning, rates={th: 2.0})["A"]]
        [[1.0, 0.0], [0.0, 2.0], [-4.0, 0.0]]
        """
        positions = self.joints(motion)
        if motion.velocity is None:
            raise InvalidGeometryError("point_motion needs the unknowns' rates: solve with rates={input: "
                                       "rate} (and accelerations=... if any); got a motion of positions only")
        zero = {name: 0.0 for name in motion.position}
        arrays = [np.stack(np.broadcast_arrays(*(values[s.name] for s in self.unknowns)), axis=-1)
                  for values in (motion.position, motion.velocity, motion.acceleration or zero)]
        given = [_keyed(argument, {} if mapping is None else mapping, self.inputs, required=False)
                 for argument, mapping in (("rates", rates), ("accelerations", accelerations))]
        inputs = [np.stack(np.broadcast_arrays(*(motion.inputs[s.name] for s in self.inputs)), axis=-1)]
        ones = np.ones_like(inputs[0][..., 0])
        for argument, values in zip(("rates", "accelerations"), given, strict=True):
            inputs.append(np.stack([require_finite(f"{argument}[{s.name}]", values.get(s.name, 0.0)) * ones
                                    for s in self.inputs], axis=-1))
        stages = {"rates": rates is None}
        if motion.acceleration is not None:  # else q̈ is taken as 0 with the given (or zero) accelerations
            stages["accelerations"] = accelerations is None
        form = self._twin()
        if form is None:
            form = self
        else:  # lengths far from unit size: evaluated in the twin's units (see .scaling)
            arrays = [values / form._units.q for values in arrays]
            inputs = [values / form._units.u for values in inputs]
        inputs[1], inputs[2] = form._input_rates(arrays, inputs, stages)
        terms = form._point_rate_fn(form._values, *arrays, *inputs)
        if form is not self:
            terms = terms * form._units.length
        return {name: (positions[name], _vector(terms, 4 * k, 2), _vector(terms, 4 * k + 2, 2))
                for k, name in enumerate(self.points)}

    def _input_rates(self, arrays, inputs, stages: dict[str, bool]):
        """The inputs' rates and accelerations that go with the motion's own: read from it where not given
        (J·q̇ + F_u·u̇ = 0 and J·q̈ + F_u·ü = −(the rest of d²F/dt²), solved for u̇, ü in least squares), and
        where given, checked to be the ones it was solved with (else the named error: a point would move
        with other rates than the links that carry it); ``stages``: "rates", "accelerations" → find (True)
        or check (False)."""
        (q, q_rate, q_acc), (u, u_rate, u_acc) = arrays, inputs
        shape = np.broadcast_shapes(q.shape[:-1], u.shape[:-1], u_rate.shape[:-1])
        flat = [np.broadcast_to(a, shape + a.shape[-1:]).reshape(-1, a.shape[-1])
                for a in (q, q_rate, q_acc, u, u_rate, u_acc)]
        q, q_rate, q_acc, u, u_rate, u_acc = flat
        found = _finite_rows(q, q_rate, u)
        at, u_at = np.where(found[:, None], q, 0.0), np.where(found[:, None], u, 0.0)

        def settle(stage, carried, terms, given):
            """``given`` where it is the input's share F_u·x = ``carried`` of the motion (``terms``: the sizes
            that cancel in it), or where ``stages`` says to read it: x by least squares."""
            if stages[stage]:
                return np.where(found[:, None], np.einsum("nij,nj->ni", np.linalg.pinv(F_u), carried), given)
            share = np.einsum("nij,nj->ni", F_u, given)
            gap, size = np.abs(share - carried).max(axis=1), (terms + np.abs(share)).max(axis=1)
            # a mismatch within 1e-8 of the terms, or below 1e-12 of an input's unit (rates near 0)
            bad = found & ~(gap <= 1e-8 * size + 1e-12 * np.abs(F_u).max(axis=(1, 2)))
            if bad.any():
                k = int(np.flatnonzero(bad)[0])
                value = np.linalg.pinv(F_u[k]) @ carried[k]
                if self._units is not None:  # a twin's (see .scaling): in the declaration's units
                    value = value * self._units.u
                names = ", ".join(f"{s.name}: {v:.6g}" for s, v in zip(self.inputs, value, strict=True))
                raise InvalidArgumentError(
                    f"{stage} are not the ones this motion was solved with (at {self._where(u, k)} its "
                    f"{'velocities' if stage == 'rates' else 'accelerations'} go with {{{names}}}): "
                    f"pass those, or leave {stage} out to read them from the motion")
            return given

        with np.errstate(all="ignore"):
            J, F_u = self._rate_terms(at, u_at)
            carried = -np.einsum("nij,nj->ni", J, q_rate)  # = F_u·u̇
            u_rate = settle("rates", carried, np.abs(carried), u_rate)
            if "accelerations" in stages:  # with u̇ known: J·q̈ + F_u·ü = −(the rest of d²F/dt²)
                rest, moved = self._rhs(at, q_rate, u, u_rate, np.zeros_like(u_acc)), np.einsum(
                    "nij,nj->ni", J, q_acc)
                u_acc = settle("accelerations", rest - moved, np.abs(rest) + np.abs(moved), u_acc)
        return u_rate.reshape(shape + u_rate.shape[-1:]), u_acc.reshape(shape + u_acc.shape[-1:])

    def joints(self, motion: Motion) -> dict[str, np.ndarray]:
        """Coordinates (m) of the declared ``points`` along a motion: name → array (..., 2).

        >>> th, x = sp.symbols("theta x")
        >>> A = sp.Matrix([sp.cos(th), sp.sin(th)])
        >>> crank = Mechanism([x - sp.cos(th)], [x], [th], points={"O": sp.zeros(2, 1), "A": A},
        ...                   links=[("O", "A")])
        >>> crank.joints(crank.solve({th: [0.0, np.pi / 2]}, guess={x: 1.0}))["A"].round(12).tolist()
        [[1.0, 0.0], [0.0, 1.0]]
        """
        if not self.points:
            raise InvalidGeometryError("joints needs points: declare points={name: Matrix([x, y])}; "
                                       "got points={}")
        names = [s.name for s in self.unknowns], [s.name for s in self.inputs]
        # a Motion of these loops, or of the same loops solved the other way round (a five-bar's inverse)
        values = {**motion.inputs, **motion.position} if isinstance(motion, Motion) else {}
        if sorted(values) != sorted(names[0] + names[1]):
            raise InvalidGeometryError(f"motion must be a Motion of this mechanism (unknowns {names[0]}, "
                                       f"inputs {names[1]}); got {motion!r}"[:400])
        q = np.stack(np.broadcast_arrays(*(values[s.name] for s in self.unknowns)), axis=-1)
        u = np.stack(np.broadcast_arrays(*(values[s.name] for s in self.inputs)), axis=-1)
        self._check_closes(motion, q, u)
        form, q, u = self._in_twin(q, u)  # lengths far from unit size: in the twin's units (see .scaling)
        xy = form._point_fn(form._values, q, u)
        if form is not self:
            xy = xy * form._units.length
        return {name: _vector(xy, 2 * k, 2) for k, name in enumerate(self.points)}

    def _check_closes(self, motion: Motion, q: np.ndarray, u: np.ndarray) -> None:
        """A motion of these loops with these numbers: where it says it converged, its values close the
        loops (each row within RESIDUAL of its typical size), else the named error — a motion of another
        machine, or of the same loops with other lengths, is not drawn with this one's."""
        leading = np.broadcast_shapes(q.shape[:-1], u.shape[:-1])
        said = np.broadcast_to(np.asarray(motion.converged, bool), leading) if np.ndim(motion.converged) \
            <= len(leading) else np.zeros(leading, bool)
        q, u = np.broadcast_to(q, leading + q.shape[-1:]), np.broadcast_to(u, leading + u.shape[-1:])
        said = said & np.isfinite(q).all(axis=-1) & np.isfinite(u).all(axis=-1)
        if not said.any():
            return
        form, q_said, u_said = self._in_twin(q[said], u[said])  # far from unit size: the twin's (.scaling)
        with np.errstate(all="ignore"):
            residual = (np.abs(form._F(q_said, u_said)) / form._scales[0]).max(axis=-1)
        if not (residual <= RESIDUAL).all():
            k = int(np.flatnonzero(~(residual <= RESIDUAL))[0])
            where = self._where(u[said], k)
            numbers = ", ".join(f"{s.name}={v:.6g}" for s, v in self.parameters.items())
            raise InvalidArgumentError(
                f"motion does not close these loops at {where} (residual {residual[k]:.2g} of a row's "
                f"typical size): it was solved for another mechanism or other numbers; solve this one "
                f"({numbers}) and pass its motion")
