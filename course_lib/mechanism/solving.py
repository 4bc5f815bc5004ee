"""Solving a motion: :meth:`Solving.solve` (closed form by σ where every block reduces, Newton with
continuation elsewhere) and the one result, a :class:`~course_lib.motion.Motion`.

One room of :class:`~course_lib.mechanism.Mechanism`, which is all of them together.
"""

from __future__ import annotations

from collections.abc import Mapping
from types import MappingProxyType

import numpy as np

from ..errors import (
    FAILURE_POLICIES,
    ConvergenceError,
    InvalidGeometryError,
    SingularJacobianError,
    UnreachableError,
    known_keywords,
    require_broadcast,
    require_choice,
    require_finite,
)
from ..motion import Deferred, Motion
from ..newton import (
    NewtonResult,
    _settings,
    newton,
)
from ..planar import scalar_or_array
from .closed_forms import LEVEL, RESIDUAL
from .compiled import _BLOCK, _finite_rows
from .continuation import _unwrap_to
from .declaration import _broadcast, _keyed, _plain
from .singular import NEAR_SINGULAR, SINGULAR

#: Instants per block of :meth:`Solving._swept`: the kernel's and the rates' temporaries stay in the cache.
_SWEPT = 16_384


def _stacked(arrays, N: int) -> np.ndarray:
    """Arrays of one shape (the inputs' rates or accelerations) side by side, (N, m); numbers given
    (broadcast, every stride 0) as a read-only view of their one row, the same at every instant."""
    if N and not any(stride for a in arrays for stride in a.strides):
        return np.broadcast_to(np.array([a[(0,) * a.ndim] for a in arrays], float), (N, len(arrays)))
    return np.stack(arrays, axis=-1).reshape(-1, len(arrays))


class Solving:
    """``solve``: a motion from the inputs, and the one result it returns."""

    @known_keywords
    def solve(self, inputs: Mapping, rates: Mapping | None = None, accelerations: Mapping | None = None,
              guess: Mapping | None = None, *, assembly: Mapping | None = None, tol: float = 1e-10,
              max_iter: int = 50, on_failure: str = "raise") -> Motion:
        """Position, and velocity and acceleration if asked, at each value of the inputs.

        ``inputs``, ``rates``, ``accelerations`` map inputs (symbol or name) to numbers or arrays,
        broadcast together (missing rates are 0).  ``guess`` picks the assembly: Newton runs from it at the
        first instant (its history in ``Motion.newton`` for one instant).  Where every block reduces to a
        closed form (:attr:`closed_forms`) each block keeps the assembly σ nearest that solution (σ = +1
        without a guess, or the σ that ``assembly`` gives by any unknown of the block, one for every instant
        or an array of them broadcast with the inputs; σ = −sign(det J_b),
        see :mod:`~course_lib.mechanism.closed_forms`; ``Motion.assembly`` gives it for every unknown of a
        block, and ``Motion.message`` names the blocks a partial ``assembly`` left at +1), and Newton only
        cross-checks; elsewhere each instant continues from its neighbour's solution (tangent predictor,
        steps subdivided and Newton's steps limited, so no instant lands on another assembly).  A sweep of
        one input is followed from its first instant outward, in increasing and in decreasing order of the
        input (the order the values come in does not matter), σ changing only at a change point, where the
        message names it; with several inputs, or a σ named by ``assembly``, each instant keeps its σ.
        Angles: the first instant's in [−π, π] (within π of the guess, given one), each next within a turn
        of its neighbour (with several inputs, which have no order of neighbours, each instant's like the
        first's); a closed form that every angle solves (the position not determined) counts as
        singular, not found.  A declaration homogeneous in its lengths and declared far from unit size
        (beyond ``UNIT_RANGE``) is solved with its lengths in units of a power of two near their typical
        size (:mod:`~course_lib.mechanism.scaling`), ``tol`` applying in those units.  Raises, unless
        ``on_failure="nan"``: ``SingularJacobianError`` (rates asked where J is singular, or a singular
        seed), ``ConvergenceError`` (no root from the guess), ``UnreachableError`` (no assembly).

        >>> th, x = sp.symbols("theta x")
        >>> motion = Mechanism([x**2 - th], [x], [th]).solve({th: [4.0, 1.0]}, {th: 1.0}, guess={x: 2.0})
        >>> motion.position["x"].tolist(), motion.velocity["x"].tolist(), motion.acceleration["x"].tolist()
        ([2.0, 1.0], [0.25, 0.5], [-0.03125, -0.25])
        """
        require_choice("on_failure", on_failure, FAILURE_POLICIES)
        tol, max_iter, _ = _settings(tol, max_iter, None, "raise")
        u_given = _keyed("inputs", inputs, self.inputs)
        rate_given = _keyed("rates", {} if rates is None else rates, self.inputs, required=False)
        acc_given = _keyed("accelerations", {} if accelerations is None else accelerations, self.inputs,
                           required=False)
        closed = self._closed_fns is not None
        chosen = self._assembly(assembly, closed, per_instant=True)
        seed = None
        if guess is not None or not closed:
            q_given = _keyed("guess", {} if guess is None else guess, self.unknowns)
            for name, value in q_given.items():
                if np.ndim(value) != 0 and np.size(value) != 1 or isinstance(value, str | bytes):
                    raise InvalidGeometryError(f"guess must give one number per unknown; got guess[{name}]="
                                               f"{value!r}")
            seed = np.array([float(require_finite(f"guess[{k}]", _plain(f"guess[{k}]", v)).ravel()[0])
                             for k, v in q_given.items()])
        named = {}
        for argument, given in (("inputs", u_given), ("rates", rate_given), ("accelerations", acc_given)):
            for name in (s.name for s in self.inputs):
                where = f"{argument}[{name}]"
                if isinstance(given.get(name), np.ma.MaskedArray):
                    raise InvalidGeometryError(f"{where} must be a plain array, not a masked one (its masked "
                                               f"entries would be solved too): give the values to solve; got "
                                               f"{given[name]!r}"[:400])
                named[where] = require_finite(where, _plain(where, given.get(name, 0.0)))
        try:
            arrays = np.broadcast_arrays(*named.values())
        except ValueError:
            shapes = {k: np.shape(v) for k, v in named.items()}
            raise InvalidGeometryError(f"inputs, rates and accelerations must broadcast to one shape; "
                                       f"got shapes {shapes}") from None
        shape, m = arrays[0].shape, len(self.inputs)
        for block, sigma in chosen.items():  # σ per instant: one per instant of the inputs
            if np.ndim(sigma):
                try:
                    chosen[block] = np.broadcast_to(sigma, shape).reshape(-1)
                except ValueError:
                    raise InvalidGeometryError(f"assembly's σ per instant must broadcast to the inputs' "
                                               f"shape {shape}; got shape {np.shape(sigma)}") from None
        # the inputs (N, m): one input as given (a view where it can be: nothing writes into u)
        u = arrays[0].reshape(-1, 1) if m == 1 else np.stack(arrays[:m], axis=-1).reshape(-1, m)
        u_rate, u_acc = ((_stacked(arrays[k * m:(k + 1) * m], len(u)) for k in (1, 2))
                         if rates is not None or accelerations is not None else (None, None))
        if not len(u):  # an empty sweep: an empty motion
            nothing = MappingProxyType({s.name: np.empty(shape) for s in self.unknowns})
            asked = rates is not None or accelerations is not None
            return Motion(position=nothing, velocity=nothing if asked else None,
                          acceleration=nothing if asked else None, converged=np.empty(shape, bool),
                          singular=np.empty(shape, bool), iterations=np.empty(shape, int),
                          inputs=MappingProxyType(dict(zip((s.name for s in self.inputs), arrays[:m],
                                                           strict=True))),
                          near_singular=np.empty(shape, bool))
        want_rates = rates is not None or accelerations is not None
        twin = self._twin()
        if twin is not None:  # lengths far from unit size: solved in units of 2^k (see .scaling)
            units = twin._units
            u, seed = u / units.u, None if seed is None else seed / units.q
            if want_rates:
                u_rate, u_acc = u_rate / units.u, u_acc / units.u
            return twin._solved(u, u_rate, u_acc, seed, chosen, shape, arrays[:m], want_rates, tol, max_iter,
                                on_failure)
        return self._solved(u, u_rate, u_acc, seed, chosen, shape, arrays[:m], want_rates, tol, max_iter,
                            on_failure)

    def _solved(self, u, u_rate, u_acc, seed, chosen, shape, inputs, want_rates, tol, max_iter, on_failure
                ) -> Motion:
        """:meth:`solve` of checked arrays: inputs ``u`` (N, m), their rates ``u_rate``, ``u_acc`` (N, m;
        None unless ``want_rates``), ``seed`` (n,) or None, σ ``chosen`` per block, the inputs' ``shape``
        and the ``inputs`` as given (for ``Motion.inputs``).  On a twin (see :mod:`.scaling`) the arrays are
        in its units and the motion comes out in the declaration's."""
        closed = self._closed_fns is not None
        paths, notes, result, shown, assembly = self._paths(u), [], None, None, None
        undetermined = np.zeros(len(u), bool)
        known, at_q = {}, None  # the cos and sin of the inputs, computed once; of q, where q is final
        stuck = np.zeros(len(u), bool)
        with np.errstate(all="ignore"):
            if seed is not None:
                result = newton(lambda q: self._F(q, u[0]), seed, jac=lambda q: self._J(q, u[0]),
                                tol=tol, max_iter=max_iter, on_failure="report")
                shown = self._shown(result, u[0])  # in the declaration's units (a twin's: converted)
            swept = closed and self._sweepable(u, paths, chosen, seed)
            if swept:  # every block a kernel, σ named, instants in order: block by block, rates alongside
                q, undetermined, sigma, swept = self._swept(u, chosen, notes, u_rate if want_rates else None,
                                                            u_acc if want_rates else None)
                stuck |= undetermined
                iterations = np.zeros(len(u), int)
            elif closed:
                target = None if result is None else result.x if result.converged else seed
                if result is not None and not result.converged:
                    notes.append(f"Newton from the guess did not converge at {self._where(u, 0)} "
                                 f"({shown.message}); the closed form gave the assembly nearest the guess")
                q, iterations, sigma, at_q, undetermined = self._closed(u, paths, target, tol, max_iter,
                                                                        notes, chosen, known)
                stuck |= undetermined
                if shape == () and result is not None:
                    iterations[0] = result.iterations
            if closed:
                blocks = self._block_of()
                found = _finite_rows(q)
                by_block = {block: scalar_or_array(np.where(found, values, 0).astype(np.int8).reshape(shape))
                            for block, values in sigma.items()}  # one array per block, shared by its unknowns
                assembly = {s.name: by_block[blocks[s.name]] for s in self.unknowns if s.name in blocks}
                left = sorted({blocks[name] for name in blocks} - set(chosen)) if chosen else []
                if left:
                    notes.append("assembly= chose no σ for the block of " + ", ".join(
                        "/".join(s.name for s in self.unknowns if blocks.get(s.name) == block)
                        for block in left)
                        + ": σ = +1 taken there")
            elif shape == ():
                where = self._where(u, 0)
                # one instant where plain Newton fails (at a limit, where the root is double and J singular)
                # gets the corrector a sweep's first instant gets: the same verdict on both routes
                found, fixed, count = result.x, bool(result.converged), result.iterations
                if not fixed:
                    found, fixed, count = self._correct(seed, u[0], tol, max_iter)
                if not fixed and np.isfinite(result.x).all():
                    found, fixed, count = self._correct(result.x, u[0], tol, max_iter)
                if on_failure == "raise" and result.ill_conditioned and not fixed:
                    raise SingularJacobianError(f"at {where}: {shown.message}", shown.x.tolist())
                if on_failure == "raise" and not fixed:
                    raise ConvergenceError(f"at {where}, from the guess: {shown.message}", result=shown)
                q = found[None, :].copy() if fixed else np.full((1, len(seed)), np.nan)
                iterations, stuck[0] = np.array([count]), result.ill_conditioned and not fixed
            else:
                start = result.x if result.converged else None
                if start is None:
                    start, fixed, _ = self._correct(seed, u[0], tol, max_iter)
                    if not fixed:
                        start = None
                    if start is None and on_failure == "raise":
                        where = self._where(u, 0)
                        if result.ill_conditioned:
                            raise SingularJacobianError(f"at {where}, the first instant: {shown.message}",
                                                        shown.x.tolist())
                        raise ConvergenceError(f"at {where}, the first instant, from the guess: "
                                               f"{shown.message}", result=shown)
                q, iterations = self._march(u, paths, start, tol, max_iter, notes)
            converged = found if closed else _finite_rows(q)  # (q as it was when found)
            if "rigid" not in self._numeric and self.links and converged.any():
                found = np.flatnonzero(converged)  # a sample spread over the motion shows a stretch
                sample = found[np.linspace(0, len(found) - 1, min(len(found), 257)).astype(int)]
                self._check_rigid(q[sample], u[sample])
            safe = q if converged.all() else np.where(converged[:, None], q, 0.0)
            at_q = at_q if at_q is not None and safe is q else dict(known)
            masks = {}

            def singular_and_near(below=None):  # the core's rule, once: with the rates, else when read
                if not masks:  # below: σ_min(J̃) < SINGULAR and < NEAR_SINGULAR, where found already
                    if below is None:
                        below = np.empty(len(u), bool), np.empty(len(u), bool)
                        with np.errstate(all="ignore"):
                            self._below(self._J(safe, u, at_q), *below)
                    masks["singular"] = converged & below[0] | stuck
                    masks["near"] = converged & below[1]
                    self._notes(notes, converged, masks["singular"], masks["near"], u, undetermined)
                return masks

            if want_rates and swept:  # found with the positions, block by block
                q_rate, q_acc, below = swept
                singular = singular_and_near(below)["singular"]
            elif want_rates:  # _BLOCK instants at a time: the temporaries stay in the cache, the memory flat
                q_rate, q_acc = np.empty(q.shape), np.empty(q.shape)
                below = np.empty(len(u), bool), np.empty(len(u), bool)
                for start in range(0, len(u), _BLOCK):
                    part = slice(start, start + _BLOCK)
                    known_part = {key: value[part] for key, value in at_q.items()}
                    J, F_u = self._rate_terms(safe[part], u[part], known_part, same_point=True)
                    self._below(J, below[0][part], below[1][part])
                    bad = ~converged[part] | below[0][part] | stuck[part]
                    q_rate[part], q_acc[part], _ = self._rates(safe[part], u[part], u_rate[part], u_acc[part],
                                                               bad, (J, F_u), known_part)
                singular = singular_and_near(below)["singular"]
        if on_failure == "raise":
            self._report(~converged, singular if want_rates else undetermined, u, closed, q, undetermined)
        if not converged.all():  # an instant is solved whole or not at all: NaN in every unknown
            q[~converged] = np.nan
        if self._units is not None:  # a twin's lengths and their rates in the declaration's units
            q = q * self._units.q
            if want_rates:
                q_rate, q_acc = q_rate * self._units.q, q_acc * self._units.q
        velocity = acceleration = None
        if want_rates:
            velocity, acceleration = self._by_name(q_rate, shape), self._by_name(q_acc, shape)

        def shaped(values):
            return scalar_or_array(values.reshape(shape))

        def later(value):  # computed now where the rates needed it, else when first read
            return value() if masks else Deferred(value)

        inputs_used = {s.name: scalar_or_array(a) for s, a in zip(self.inputs, inputs, strict=True)}
        return Motion(position=self._by_name(q, shape), velocity=velocity, acceleration=acceleration,
                      converged=shaped(converged), iterations=shaped(iterations),
                      singular=later(lambda: shaped(singular_and_near()["singular"])),
                      near_singular=later(lambda: shaped(singular_and_near()["near"])),
                      inputs=MappingProxyType(inputs_used), newton=shown if shape == () else None,
                      message=later(lambda: singular_and_near() and "; ".join(notes)),
                      assembly=None if assembly is None else MappingProxyType(assembly))

    def _sweepable(self, u, paths, chosen, seed) -> bool:
        """Whether :meth:`_swept` solves this sweep: every block a registered kernel, σ named for each by
        ``assembly=`` (no change point to follow), no guess, and the instants in order (one input
        increasing from the first, or several inputs, which have no order of neighbours)."""
        blocks = self._forms
        return (seed is None and len(self._kernels) == len(blocks) and len(chosen) == len(blocks)
                and (u.shape[1] > 1 or len(paths) == 1 and len(paths[0]) == len(u)  # every instant once:
                     and bool((paths[0][1:] > paths[0][:-1]).all())))  # increasing, so 0, 1, …, N − 1

    def _swept(self, u, chosen, notes, u_rate=None, u_acc=None):
        """Positions (N, n), the instants not determined, σ per block and, with ``u_rate``, (q̇, q̈, (where
        σ_min(J̃) < SINGULAR, where < NEAR_SINGULAR)): _SWEPT instants at a time, each block's kernel, the
        angles continued from the block before (the same bits as :meth:`_continuous` on the whole) and the
        rates of the block while its values are in the cache (the kernel route of :meth:`solve`, see
        :meth:`_sweepable`)."""
        N, n = u.shape[0], len(self.unknowns)
        angles = [j for j, s in enumerate(self.unknowns) if s in self._structure["angles"]]
        several, inputs = u.shape[1] > 1, {s.name for s in self.inputs}
        q, undetermined = np.empty((N, n)), np.zeros(N, bool)
        sigma = {name: np.empty(N, np.int8) for name in chosen}
        # q̇, q̈ by row, and where σ_min(J̃) < SINGULAR and < NEAR_SINGULAR
        rates = None if u_rate is None else (np.empty((n, N)), np.empty((n, N)), np.empty(N, bool),
                                             np.empty(N, bool))
        followed = previous = turns = None  # the angles followed from instant 0, their last value, turns
        for start in range(0, N, _SWEPT):
            part = slice(start, start + _SWEPT)
            q_part, u_part = q[part], u[part]
            if len(self._forms) > 1:  # a later block's unknowns NaN while an earlier's solve
                q_part[:] = np.nan
            at = {name: value if np.ndim(value) == 0 else value[part] for name, value in chosen.items()}
            known = {}  # the cos and sin the kernels give
            for form in self._forms:
                first = self.unknowns.index(form.unknowns[0])
                name = form.unknowns[0].name
                in_order = None  # σ named for every block (see _sweepable): no path to pick σ or follow it on
                sigma[name][part], level, trig = self._kernel_block(self._kernels[name], form, q_part, u_part,
                                                                    in_order, None, at, notes,
                                                                    trig_wanted=True)
                known |= trig
                undetermined[part] |= np.isnan(q_part[:, first]) & (level >= -LEVEL)
            if angles and several:  # each instant's angles in [−π, π]
                q_part[:, angles] = _unwrap_to(q_part[:, angles], 0.0)
            elif angles:
                if followed is None:  # instant 0 decides which angles are followed (as _continuous)
                    followed = [j for j in angles if np.isfinite(q_part[0, j])]
                    q_part[0, followed] = _unwrap_to(q_part[0, followed], 0.0)
                    previous, turns = q_part[0, followed].copy(), np.zeros(len(followed))
                lost = [j for j in angles if j not in followed]
                if lost:
                    q_part[:, lost] = _unwrap_to(q_part[:, lost], 0.0)
                if followed:
                    previous, turns = self._turned(q_part, followed, previous, turns)
            if rates is not None:
                found = _finite_rows(q_part)
                safe = q_part
                if not found.all():  # the unknowns' cos and sin taken at 0 where not found, as their values
                    safe = np.where(found[:, None], q_part, 0.0)
                    known = {key: value for key, value in known.items() if key[0] in inputs}
                # J, q̇, q̈ in one pass; rates the same at every instant given once (their products with
                # the parameters then computed once)
                given = [a[:1] if a.strides[0] == 0 else a[part] for a in (u_rate, u_acc)]
                velocity, acceleration = rates[0][:, part], rates[1][:, part]
                fused = self._fused(safe, u_part, *given, known, into=(velocity, acceleration))
                J, F_u = (fused[0], None) if fused is not None else self._rate_terms(safe, u_part, known,
                                                                                     same_point=True)
                self._below(J, rates[2][part], rates[3][part])
                bad = ~found | rates[2][part] | undetermined[part]
                if fused is not None:  # q̇ and q̈ written in their rows already
                    if bad.any():
                        velocity[:, bad] = acceleration[:, bad] = np.nan
                else:
                    q_rate, q_acc, _ = self._rates(safe, u_part, u_rate[part], u_acc[part], bad, (J, F_u),
                                                   known)
                    velocity[:], acceleration[:] = q_rate.T, q_acc.T
        # q̇ and q̈ (N, n) as views of their rows: each unknown's rates one contiguous array
        return q, undetermined, sigma, None if rates is None else (rates[0].T, rates[1].T, rates[2:])

    @staticmethod
    def _turned(q_part, columns, previous, turns):
        """Whole turns taken off ``columns`` of one block so each step is within π, counted on from the
        block before (``previous``: its last found values as solved, ``turns``: its count); returns the
        two for the next block.  Rows not found are skipped, as :meth:`_continuous` does."""
        values = q_part[:, columns]
        found = _finite_rows(values)
        rows = np.flatnonzero(found) if not found.all() else None
        if rows is not None:
            values = values[rows]
        if not len(values):
            return previous, turns
        # the steps from ``previous`` on (the first block's first step is 0), in the layout of ``values``
        # (columns taken by a list: one column after the other, which a row-by-row array would cross slowly)
        steps = np.empty_like(values)
        np.subtract(values[:1], previous, out=steps[:1])
        np.subtract(values[1:], values[:-1], out=steps[1:])
        steps /= 2 * np.pi
        wraps = np.round(steps, out=steps)
        if wraps.any() or turns.any():
            counted = turns + np.cumsum(wraps, axis=0)
            kept = values - 2 * np.pi * counted
            for k, j in enumerate(columns):
                if rows is None:
                    q_part[:, j] = kept[:, k]
                else:
                    q_part[rows, j] = kept[:, k]
            turns = counted[-1]
        return values[-1].copy(), turns

    def _notes(self, notes, converged, singular, near, u, undetermined) -> None:
        """The singular and near-singular instants and the limits met, added to ``notes`` in words."""
        for mask, what in ((singular & ~undetermined, f"J is singular (its smallest singular value, scaled, "
                                                      f"below {SINGULAR:.0e}: a toggle, limit or change "
                                                      "point; the rates are undefined)"),
                           (near & ~singular, f"near a singular configuration (J's smallest singular value, "
                                               f"scaled, below {NEAR_SINGULAR:.0e}: the rates are large and "
                                               "sensitive)"),
                           (undetermined, "the position is not determined (every value of a closed form "
                                          "solves it: a change point)"),
                           (~converged & ~undetermined, "no assembly (beyond a limit position, or not "
                                                        "reached)")):
            if mask.any():
                first = int(np.flatnonzero(mask)[0])
                count = f" ({int(mask.sum())} of {mask.size} instants)" if mask.size > 1 else ""
                notes.append(f"{what} at {self._where(u, first)}{count}")

    def _report(self, bad, singular, u, closed, q, undetermined) -> None:
        """Raise the named error of the first bad instant (see :meth:`solve`), naming the loop that failed."""
        if not (bad.any() or singular.any()):
            return
        first = int(np.flatnonzero(bad | singular)[0])
        where = self._where(u, first)
        count = f" ({int((bad | singular).sum())} of {bad.size} instants, first at index {first})" \
            if bad.size > 1 else ""
        loops = "loops" if len(self._loops) > 1 else "loop"
        if undetermined[first]:
            loop = self._failing(q, u, first, False)
            raise SingularJacobianError(f"the position is not determined at {where}{count}{loop}: every "
                                        f"value of the closed form closes the {loops} there (a change point, "
                                        "such as a pin on a pivot between two equal links), so neither the "
                                        "position nor the rates are defined; move the input off it")
        if singular[first]:
            loop = self._failing(q, u, first, True)
            raise SingularJacobianError(f"J is singular at {where}{count}{loop}: the mechanism is at a "
                                        "toggle, limit or change point (J's smallest singular value, "
                                        f"scaled, below {SINGULAR:.0e}), where the rates are undefined; ask "
                                        "for positions only, or move the input off it")
        loop = self._failing(q, u, first, False)
        if closed:
            raise UnreachableError(f"the {loops} cannot be closed at {where}{count}{loop}: the closed "
                                   "form's quadratic has no real root there (b² − 4ac < 0), so no assembly "
                                   "exists", mask=bad)
        if first == 0:
            raise ConvergenceError(f"Newton did not converge at {where} from the guess{count}{loop}: "
                                   "no assembly near the guess, or none at all")
        raise UnreachableError(f"the {loops} cannot be closed at {where}{count}{loop}, continuing from the "
                               "previous instant: the mechanism cannot follow the input there", mask=bad)

    def _failing(self, q, u, k, singular) -> str:
        """The declared loops at fault at instant ``k``, as ", in loops[i]" ("" for one loop): where J is
        singular, those of the block whose own part of J̃ is nearest singular; where no position was
        found, the closed-form block with no root, or else the rows furthest from closing at the nearest
        solved instant's position."""
        rows_of = {row: k_loop for k_loop, rows in enumerate(self._loops) for row in rows}
        scale_rows, scale_columns = self._scales
        with np.errstate(all="ignore"):
            if singular:  # the block (rows solved together) whose own scaled J is nearest singular
                J = self._J(q[k:k + 1], u[k:k + 1])[0] / scale_rows[:, None] / scale_columns[None, :]
                rows = min(self._structure["blocks"], key=lambda block: np.linalg.svd(
                    J[np.ix_(*block)], compute_uv=False)[-1])[0]
            else:
                missing = [j for j in range(len(self.unknowns)) if not np.isfinite(q[k, j])]
                blocks = self._structure["blocks"]
                # closed forms solve the blocks in turn, so the first block with no root is at fault
                if len(missing) < len(self.unknowns) or len(blocks) == 1 or self._closed_fns is not None:
                    rows = next((r for r, columns in blocks if set(columns) & set(missing)), [])
                else:
                    solved = np.flatnonzero(np.isfinite(q).all(axis=1))
                    if not len(solved):
                        return ""
                    near = solved[np.argmin(np.abs(solved - k))]
                    residual = np.abs(self._F(q[near:near + 1], u[k:k + 1])[0]) / scale_rows
                    rows = np.flatnonzero(residual >= 0.5 * residual.max())
        loops = sorted({rows_of[int(r)] for r in rows})
        if not loops or len(self._loops) == 1:  # one loop: nothing to name
            return ""
        return ", in " + " and ".join(f"loops[{i}]" for i in loops)

    def motion_of(self, position: Mapping, inputs: Mapping, velocity: Mapping | None = None,
                  acceleration: Mapping | None = None, *, converged=None, singular=None, near_singular=None,
                  message: str = "", assembly: Mapping | None = None, iterations=0,
                  newton: NewtonResult | None = None, kind: type[Motion] = Motion, **extra) -> Motion:
        """A :class:`Motion` of this mechanism from values found another way (a machine's own closed form):
        ``position`` and the rates keyed by the unknowns' names, ``inputs`` by the inputs', broadcast
        together.  ``converged`` defaults to "every unknown finite and the loops closed there" (each row's
        residual within 1e-8 of its typical size); ``singular`` and ``near_singular`` to
        the core's rule where converged; ``iterations`` (default 0) and ``newton`` say how it was found.
        ``kind``: a machine's own :class:`Motion` (its result type, with its names for the values and its
        ``extra`` fields).

        >>> th, x = sp.symbols("theta x")
        >>> follower = Mechanism([x - sp.cos(th)], [x], [th])
        >>> motion = follower.motion_of({"x": [1.0, 0.0]}, {"theta": [0.0, np.pi / 2]})
        >>> motion.converged.tolist(), motion.singular.tolist(), motion.iterations.tolist()
        ([True, True], [False, False], [0, 0])
        """
        unknowns, inputs_named = [s.name for s in self.unknowns], [s.name for s in self.inputs]
        for argument, given, names in (("position", position, unknowns), ("inputs", inputs, inputs_named),
                                       ("velocity", velocity, unknowns),
                                       ("acceleration", acceleration, unknowns)):
            if given is not None and (not isinstance(given, Mapping) or sorted(given) != sorted(names)):
                raise InvalidGeometryError(f"{argument} must map each of {names} to its values; got {given!r}"
                                           [:400])
        named = {f"position[{k}]": position[k] for k in unknowns} | {f"inputs[{k}]": inputs[k]
                                                                      for k in inputs_named}
        for rates_name, rates in (("velocity", velocity), ("acceleration", acceleration)):
            if rates is not None:
                named |= {f"{rates_name}[{k}]": rates[k] for k in unknowns}
        arrays = dict(zip(named, require_broadcast(**{k: require_finite(k, v, allow_nan=True)
                                                         for k, v in named.items()}), strict=True))

        def part(prefix, names, given):
            return None if given is None else {k: arrays[f"{prefix}[{k}]"] for k in names}

        if converged is None:  # found another way: a position that does not close the loops is not found
            shape = np.shape(next(iter(arrays.values())))  # broadcast together above
            q, u, found = self._flat(part("position", unknowns, position),
                                     part("inputs", inputs_named, inputs), shape)
            form, q, u = self._in_twin(q, u)  # lengths far from unit size: the twin's units (see .scaling)
            with np.errstate(all="ignore"):
                residual = np.abs(form._F(q, u)) / form._scales[0]
            converged = (found & (residual.max(axis=1) <= RESIDUAL)).reshape(shape)
        return self._motion(
            part("position", unknowns, position), part("inputs", inputs_named, inputs),
            part("velocity", unknowns, velocity), part("acceleration", unknowns, acceleration),
            converged=converged, singular=singular, near_singular=near_singular, message=message,
            assembly=assembly, iterations=iterations, newton=newton, kind=kind, **extra)

    def _motion(self, position, inputs, velocity=None, acceleration=None, *, converged=None, singular=None,
                near_singular=None, message="", assembly=None, iterations=0, newton=None, kind=Motion,
                **extra) -> Motion:
        """:meth:`motion_of` of values already checked (a machine's own, keyed by the declared names):
        broadcast, shaped, and the singularity masks and the assembly not given left to the core's rules,
        computed when first read."""
        values = [*position.values(), *inputs.values(), *(velocity or {}).values(),
                  *(acceleration or {}).values()]
        shape = np.broadcast_shapes(*(np.shape(v) for v in values))

        def shaped(value):
            return scalar_or_array(_broadcast(value, shape))

        def by_name(values):
            return None if values is None else MappingProxyType({k: shaped(v) for k, v in values.items()})

        if converged is None:
            converged = np.logical_and.reduce([np.isfinite(v) for v in position.values()])
        converged = shaped(np.asarray(converged, bool))
        found = {}

        def smallest():  # the core's σ_min(J̃), once, for whichever mask is read first
            if not found:
                found["smallest"] = self._smallest_where(position, inputs, shape)
            return found["smallest"]

        if singular is None:
            singular = Deferred(lambda: shaped(np.asarray(converged) & ~(smallest() >= SINGULAR)))
        else:
            singular = shaped(np.asarray(singular, bool))
        if near_singular is None:
            near_singular = Deferred(lambda: shaped(np.asarray(converged) & ~(smallest() >= NEAR_SINGULAR)))
        else:
            near_singular = shaped(np.asarray(near_singular, bool))
        return kind(position=by_name(position), velocity=by_name(velocity),
                    acceleration=by_name(acceleration),
                    converged=converged, singular=singular, iterations=shaped(np.asarray(iterations)),
                    newton=newton, inputs=by_name(inputs), near_singular=near_singular, message=message,
                    assembly=(MappingProxyType(dict(assembly)) if assembly is not None
                              else Deferred(lambda: self._frozen_assembly(position, inputs, shape))), **extra)

    def _frozen_assembly(self, position, inputs, shape):
        """The core's σ of values found another way (see ``_assembly_at``), read-only; None without closed
        forms."""
        found = self._assembly_at(position, inputs, shape)
        return None if found is None else MappingProxyType(found)
