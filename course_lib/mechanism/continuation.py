"""Continuation: a sweep followed instant by instant from its neighbour's solution (tangent predictor,
Newton corrector, steps subdivided), where no closed form solves the loops.

One room of :class:`~course_lib.mechanism.Mechanism`, which is all of them together.
"""

from __future__ import annotations

import heapq

import numpy as np

from ..symbolic import is_angle
from ..thresholds import FLIP_NEAR, FLIP_SMOOTH
from .singular import SINGULAR

#: A continuation step changes no unknown by more than this (radians, or typical lengths).
MAX_CHANGE = 0.1


#: A corrector step moves no unknown by more than this (radians, or typical lengths).
MAX_STEP = 0.5

#: A step whose change of orientation does not look like a change point crossed (``FLIP_SMOOTH``,
#: ``FLIP_NEAR`` of :mod:`course_lib.thresholds`) is taken again in halves, down to FLIP_DEPTH halvings.
FLIP_DEPTH = 16

#: A sweep of one input with at least this many instants is followed on its path first (anchors a spacing
#: ``ANCHOR_SPACING`` of the input apart, every step recorded), then every instant solved at once by Newton
#: from the path's tangent prediction (:meth:`Continuation._batched`).
BATCH_MIN = 64
ANCHOR_SPACING = 0.05

#: Predictor–corrector steps one instant may take before it is given up as not reached: an unknown that
#: grows without bound (x = 1/s followed towards s = 0) would otherwise be followed MAX_CHANGE at a time.
MAX_STEPS = 1000


def _unwrap_to(values: np.ndarray, target: np.ndarray) -> np.ndarray:
    """``values`` shifted by whole turns to within π of ``target`` (NaN stays NaN)."""
    return values - 2 * np.pi * np.round((values - target) / (2 * np.pi))


class Continuation:
    """Newton with continuation: predictor, corrector and steps subdivided along a sweep."""

    @staticmethod
    def _paths(u: np.ndarray) -> list[np.ndarray]:
        """The orders a sweep follows, each from instant 0: one input outward from it in increasing and in
        decreasing order of the input; several inputs in the order given."""
        N, m = u.shape
        if N == 1:
            return [np.array([0])]
        if m > 1 or (u[1:, 0] >= u[:-1, 0]).all():  # several inputs, or one increasing from instant 0
            return [np.arange(N)]
        order = np.argsort(u[:, 0], kind="stable")
        at = int(np.flatnonzero(order == 0)[0])
        return [p for p in (order[at:], order[:at + 1][::-1]) if len(p) > 1]

    def _distance(self, a: np.ndarray, b: np.ndarray, columns=None) -> np.ndarray:
        """max over unknowns of |a − b| in typical units (angles compared modulo a turn)."""
        columns = range(len(self.unknowns)) if columns is None else columns
        angles = self._structure["angles"]
        scale = self._scales[1]
        largest = None
        for j in columns:  # the operations of _unwrap_to and np.max, in place
            gap = np.asarray(np.subtract(a[..., j], b[..., j]))  # an array even at one instant
            if self.unknowns[j] in angles:
                turns = np.divide(gap, 2 * np.pi, out=np.empty_like(gap))
                np.round(turns, out=turns)
                turns *= 2 * np.pi
                gap -= turns
            np.abs(gap, out=gap)
            gap *= scale[j]
            largest = gap if largest is None else np.maximum(largest, gap, out=largest)
        if largest is None:
            return np.max([], axis=0)
        return largest[()] if largest.ndim == 0 else largest

    def _orientation(self, q, u) -> float:
        """The sign of det J̃ at one instant (J scaled by the typical sizes), 0 where J is singular there: the
        two assemblies of a block have opposite signs, so a change of sign along a motion is a change point
        crossed, or a step that reached the other assembly."""
        return float(self._orientations(np.asarray(q)[None], np.asarray(u)[None])[0])

    def _correct(self, q, u, tol, max_iter) -> tuple[np.ndarray, bool, int]:
        """Newton from ``q`` at one instant, steps by the least-squares solve of the scaled J (the smallest
        singular values dropped: no huge step near a singularity) and no larger than MAX_STEP."""
        rows, columns = self._scales
        q, step = np.array(q, dtype=float), np.inf
        for k in range(max_iter + 1):
            F, J = self._newton_terms(q, u)
            if not (np.isfinite(F).all() and np.isfinite(J).all()):
                return q, False, k
            if step < tol and np.sqrt(F @ F) <= tol:
                return q, True, k
            if k == max_iter:
                break
            U, S, Vt = np.linalg.svd(J / rows[:, None] / columns[None, :])
            if not S[0] > 0:
                return q, False, k
            keep = S > 1e-10 * S[0]
            change = Vt[keep].T @ ((U[:, keep].T @ (-F / rows)) / S[keep])
            largest = np.abs(change).max()
            if largest > MAX_STEP:
                change *= MAX_STEP / largest
            delta = change / columns
            q, step = q + delta, float(np.sqrt(delta @ delta))
        # at a toggle or limit the root is double: F falls to round-off while the steps only halve, so
        # the step test cannot pass there; a vanishing residual where J is singular is the root itself
        F, J = self._newton_terms(q, u)
        if np.sqrt(F @ F) <= tol and not self._smallest(J) >= SINGULAR:
            return q, True, max_iter
        return q, False, max_iter

    def _advance(self, q, u_from, u_to, tol, max_iter, smallest: float = 1e-13, depth: int = 0,
                 record: list | None = None) -> tuple[np.ndarray | None, int]:
        """The solution at ``u_to`` continued from ``q`` at ``u_from``: tangent predictor, Newton corrector,
        the step halved until the corrector lands near the prediction (no other assembly); a step over which
        J's orientation changes is followed again in halves (``depth``: how many times already, up to
        FLIP_DEPTH), whose end is kept, on the same orientation (a near miss) or not (a change point
        crossed); None once the step would be below ``smallest`` (a fraction of the whole) or after
        MAX_STEPS steps.  ``record``: receives (u, q) at the end of every step taken."""
        step_u = u_to - u_from
        if not step_u.any():
            return q.copy(), 0
        columns = self._scales[1]
        angles = [j for j, s in enumerate(self.unknowns) if s in self._structure["angles"]]
        done, h, count, steps = 0.0, 0.5 if depth else 1.0, 0, 0
        sign = self._orientation(q, u_from)
        while done < 1.0:
            h, steps = min(h, 1.0 - done), steps + 1
            if h < smallest or steps > MAX_STEPS:
                return None, count
            here = u_from + done * step_u
            J, F_u = self._rate_terms(q, here)
            smallest_here = self._smallest(J)
            prediction = q
            if smallest_here >= SINGULAR:
                tangent = np.linalg.solve(J, -(F_u @ step_u))
                prediction = q + h * tangent
                change = float(np.max(np.abs(h * tangent) * columns))
                if change > MAX_CHANGE:
                    h *= 0.9 * MAX_CHANGE / change
                    continue
            else:
                change = MAX_CHANGE
            there = u_from + (done + h) * step_u
            found, fixed, used = self._correct(prediction, there, tol, max_iter)
            count += used
            if fixed:
                found[angles] = _unwrap_to(found[angles], prediction[angles])
                now = self._orientation(found, there)
                off = float(np.max(np.abs(found - prediction) * columns))
                close = off <= max(0.5 * change, 1e-6)
                moved = float(np.max(np.abs(found - q) * columns)) if close and sign and now != sign else 0.0
                if close and sign and now and now != sign and depth < FLIP_DEPTH and (
                        off > FLIP_SMOOTH * moved
                        or smallest_here + self._smallest(self._J(found, there)) > FLIP_NEAR * moved):
                    # not like a change point crossed (FLIP_SMOOTH, FLIP_NEAR): maybe the other assembly
                    # where the two come near, so the step again in halves
                    halves, used = self._advance(q, here, there, tol, max_iter, smallest, depth + 1)
                    count += used
                    if halves is not None:
                        halves[angles] = _unwrap_to(halves[angles], found[angles])
                        found, now = halves, self._orientation(halves, there)
                if close:
                    # a step ending within rounding of the end ends it (else a last step of one ulp is
                    # refused as too small, and the instant lost)
                    q, done, h = found, (1.0 if done + h >= 1.0 - 1e-12 else done + h), min(2 * h, 1.0)
                    sign = now or sign
                    if record is not None:
                        record.append((u_to if done == 1.0 else there, q))
                    continue
            h *= 0.5
        return q, count

    def _march(self, u, paths, start, tol, max_iter, notes) -> tuple[np.ndarray, np.ndarray]:
        """Positions along the paths from ``start`` at instant 0 (None: nothing found there)."""
        N, n = len(u), len(self.unknowns)
        q, iterations = np.full((N, n), np.nan), np.zeros(N, int)
        if start is None:
            return q, iterations
        q[0] = start

        def orientation(k):
            return self._orientation(q[k], u[k])

        if u.shape[1] > 1 and N > 2:  # several inputs: each instant continued from a near neighbour
            self._spread(q, iterations, u, tol, max_iter, notes, orientation)
            return q, iterations
        for path in paths:
            if len(path) >= BATCH_MIN and self._batched(q, iterations, u, path, tol, max_iter, notes):
                continue
            reached, signs = [path[0]], [orientation(path[0])]
            for k in path[1:]:
                found, iterations[k] = self._advance(q[reached[-1]], u[reached[-1]], u[k], tol, max_iter)
                if found is None:  # the motion stops before u[k] (a limit): the instants beyond it too
                    break
                q[k] = found
                reached.append(k)
                signs.append(orientation(k))
            self._note_change_points(u, reached, np.array(signs), notes)
        return q, iterations

    def _note_change_points(self, u, instants, signs, notes) -> None:
        """The change points met along a path, added to ``notes``: between two consecutive ``instants``
        (found, in the path's order) where J's orientation (``signs``, 0 where singular) differs from the
        last nonzero one before it."""
        given = signs != 0
        last = np.maximum.accumulate(np.where(given, np.arange(len(signs)), -1))
        before = np.r_[-1, last[:-1]]
        for k in np.flatnonzero(given & (before >= 0) & (signs != signs[np.maximum(before, 0)])):
            notes.append(f"the assemblies meet (a change point) between {self._where(u, instants[k - 1])} "
                         f"and {self._where(u, instants[k])}: the motion continues on the smooth one")

    def _batched(self, q, iterations, u, path, tol, max_iter, notes) -> bool:
        """The instants of ``path`` (one input, in order, ``q[path[0]]`` solved) solved together: the path
        followed by :meth:`_advance` from anchor to anchor (instants ANCHOR_SPACING of the input apart),
        every step it takes recorded; each instant predicted from the last recorded step before it by the
        tangent there, then Newton on all at once (:func:`~course_lib.newton.newton_batch`).  An instant is
        kept where Newton converged near its prediction with J's orientation of that step, which the path
        keeps to its next step; the others are continued one by one from the instant before.  The change
        points met are added to ``notes`` as :meth:`_march` does.  False (nothing written) where the path
        cannot be followed from anchor to anchor (a limit, or a stretch where the loops do not close): the
        caller goes instant by instant."""
        from ..newton import newton_batch

        units = self._input_units()
        along = u[path] / units
        travelled = np.r_[0.0, np.cumsum(np.abs(np.diff(along, axis=0)).sum(axis=1))]
        stage = np.floor(travelled / ANCHOR_SPACING) + np.arange(len(path)) // 4096
        anchors = [*np.flatnonzero(np.diff(stage) > 0) + 1, len(path) - 1]  # a new stage, and the end
        record = [(u[path[0]], q[path[0]])]
        for b in anchors:
            end, _ = self._advance(record[-1][1], record[-1][0], u[path[b]], tol, max_iter, record=record)
            if end is None:
                return False
        at_u, at_q = np.array([r[0] for r in record]), np.array([r[1] for r in record])
        J, F_u = self._rate_terms(at_q, at_u)
        flat = ~(self._smallest(J) >= SINGULAR)  # no tangent there: predict the recorded position itself
        J = np.where(flat[:, None, None], np.eye(J.shape[-1]), J)
        tangents = np.where(flat[:, None, None], 0.0, np.linalg.solve(J, -F_u))  # (R, n, m)
        signs = self._orientations(at_q, at_u)
        # each instant from the last recorded step at or before it, by the distance travelled along the input
        recorded = np.r_[0.0, np.cumsum(np.abs(np.diff(at_u / units, axis=0)).sum(axis=1))]
        nearest = np.clip(np.searchsorted(recorded, travelled + 1e-12, side="right") - 1, 0, len(record) - 1)
        prediction = at_q[nearest] + np.einsum("knm,km->kn", tangents[nearest], u[path] - at_u[nearest])
        rest = path[1:]
        with np.errstate(all="ignore"):
            result = newton_batch(self.newton_function(u[rest]), prediction[1:], jac=True, tol=tol,
                                  max_iter=max_iter)
        found = result.x
        angles = [j for j, s in enumerate(self.unknowns) if s in self._structure["angles"]]
        found[:, angles] = _unwrap_to(found[:, angles], prediction[1:, angles])
        change = self._distance(prediction[1:], at_q[nearest[1:]])
        with np.errstate(all="ignore"):
            close = (np.asarray(result.converged) & ~np.asarray(result.ill_conditioned)
                     & (self._distance(found, prediction[1:]) <= np.maximum(0.5 * change, 1e-6)))
        # kept only on the orientation of its recorded step, where the path keeps it to the next one (an
        # instant beside a change point, or where J is singular, goes one by one)
        following = signs[np.minimum(nearest[1:] + 1, len(record) - 1)]
        expected = np.where(following == signs[nearest[1:]], signs[nearest[1:]], 0.0)
        now = self._orientations(np.where(close[:, None], found, 0.0), u[rest])
        close &= (now == expected) & (expected != 0)
        q[rest] = np.where(close[:, None], found, np.nan)
        iterations[rest] = np.asarray(result.iterations)
        orientation = np.r_[signs[0], now]
        for k in np.flatnonzero(~close):  # the others one by one, from the instant before
            before, after = path[k], path[k + 1]
            if np.isfinite(q[before]).all():
                step, iterations[after] = self._advance(q[before], u[before], u[after], tol, max_iter)
                if step is not None:
                    q[after] = step
                    orientation[k + 1] = self._orientation(step, u[after])
        reached = np.isfinite(q[path]).all(axis=1)
        self._note_change_points(u, path[reached], orientation[reached], notes)
        return True

    def _orientations(self, q, u) -> np.ndarray:
        """:meth:`_orientation` of many instants at once, q (N, n), u (N, m)."""
        rows, columns = self._scales
        with np.errstate(all="ignore"):
            det = np.linalg.det(self._J(q, u) / rows[:, None] / columns[None, :])
        return np.where(np.abs(det) > SINGULAR, np.sign(det), 0.0)

    def _input_units(self) -> np.ndarray:
        """A unit for each input: 1 for an angle, the parameters' typical length for any other."""
        sizes = [abs(v) for v in self._values if v != 0.0]
        length = float(np.median(sizes)) if sizes else 1.0
        return np.array([1.0 if all(is_angle(row, s) for row in self.equations if row.has(s)) else length
                         for s in self.inputs])

    def _spread(self, q, iterations, u, tol, max_iter, notes, orientation) -> None:
        """A sweep of several inputs (a grid, or points in any order), which has no order of neighbours:
        from instant 0, each instant continued from a solved neighbour (the shortest step first: Prim's
        order over each instant's 8 nearest, inputs measured in radians and typical lengths, an angle a turn
        apart the same; each instant tried from two neighbours at most), never across the sweep; where no
        step reaches an instant (a hole of the workspace between), Newton from the nearest solved instants'
        positions.  Either is kept only on the neighbour's assembly: the orientation of J (the sign of
        det J̃) kept, as each instant solved alone on that assembly would be."""
        from scipy.spatial import cKDTree

        count, units = min(len(u), 9), self._input_units()
        turning = units == 1.0  # angle inputs: a turn apart is the same instant (the loops see cos, sin)
        places = np.column_stack([*(u[:, ~turning] / units[~turning]).T,
                                  *np.cos(u[:, turning]).T, *np.sin(u[:, turning]).T])
        distances, neighbours = cKDTree(places).query(places, k=count)

        def toward(parent, k):  # u[k], its angles within half a turn of u[parent]'s
            target = u[k].copy()
            target[turning] = _unwrap_to(target[turning], u[parent][turning])
            return target
        signs = np.zeros(len(u))
        signs[0] = orientation(0)
        done = np.zeros(len(u), bool)
        done[0] = True
        heap, tried, attempts = [], set(), np.zeros(len(u), int)

        def reached(parent, k, found) -> bool:
            q[k] = found
            sign = orientation(k)
            if sign and signs[parent] and sign != signs[parent]:  # the other assembly: not this motion
                q[k] = np.nan
                return False
            signs[k], done[k] = sign or signs[parent], True
            for d, j in zip(distances[k][1:], neighbours[k][1:], strict=True):
                if not done[j]:
                    heapq.heappush(heap, (float(d), int(k), int(j)))
            return True

        reached(0, 0, q[0])
        while True:
            while heap:
                _, parent, k = heapq.heappop(heap)
                if done[k] or attempts[k] >= 2:  # twice out of reach by a step: a hole, likely
                    continue
                attempts[k] += 1
                # a step that must be cut below 1e-4 of itself meets a hole: left to the Newton below
                found, used = self._advance(q[parent], u[parent], toward(parent, k), tol, min(max_iter, 15),
                                            smallest=1e-4)
                iterations[k] += used
                if found is not None:
                    reached(parent, k, found)
            jumped = False  # no step reaches what is left: Newton from the nearest solved instants, once each
            left, solved = np.flatnonzero(~done), np.flatnonzero(done)
            if not len(left):
                return
            nearest = solved[cKDTree(places[solved]).query(places[left], k=min(len(solved), 4))[1]
                             .reshape(len(left), -1)]
            for k, near in zip(left, nearest, strict=True):
                for parent in near:
                    if done[parent] and (int(parent), int(k)) not in tried:
                        tried.add((int(parent), int(k)))
                        found, fixed, used = self._correct(q[parent], u[k], tol, max_iter)
                        iterations[k] += used
                        if fixed and reached(int(parent), int(k), found):
                            jumped = True
                            break
            if not jumped:
                return
