"""Continuation: a sweep followed instant by instant from its neighbour's solution (tangent predictor,
Newton corrector, steps subdivided), where no closed form solves the loops.

One room of :class:`~course_lib.mechanism.Mechanism`, which is all of them together.
"""

from __future__ import annotations

import numpy as np

from .singular import SINGULAR

#: A continuation step changes no unknown by more than this (radians, or typical lengths).
MAX_CHANGE = 0.1


#: A corrector step moves no unknown by more than this (radians, or typical lengths).
MAX_STEP = 0.5


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
        if m > 1 or (np.diff(u[:, 0]) >= 0).all():  # several inputs, or one increasing from instant 0
            return [np.arange(N)]
        order = np.argsort(u[:, 0], kind="stable")
        at = int(np.flatnonzero(order == 0)[0])
        return [p for p in (order[at:], order[:at + 1][::-1]) if len(p) > 1]

    def _distance(self, a: np.ndarray, b: np.ndarray, columns=None) -> np.ndarray:
        """max over unknowns of |a − b| in typical units (angles compared modulo a turn)."""
        columns = range(len(self.unknowns)) if columns is None else columns
        angles = self._structure["angles"]
        scale = self._scales[1]
        gaps = []
        for j in columns:
            gap = a[..., j] - b[..., j]
            if self.unknowns[j] in angles:
                gap = _unwrap_to(gap, 0.0)
            gaps.append(np.abs(gap) * scale[j])
        return np.max(gaps, axis=0)

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

    def _advance(self, q, u_from, u_to, tol, max_iter) -> tuple[np.ndarray | None, int]:
        """The solution at ``u_to`` continued from ``q`` at ``u_from``: tangent predictor, Newton corrector,
        the step halved until the corrector lands near the prediction (no other assembly)."""
        step_u = u_to - u_from
        if not step_u.any():
            return q.copy(), 0
        columns = self._scales[1]
        angles = [j for j, s in enumerate(self.unknowns) if s in self._structure["angles"]]
        done, h, count = 0.0, 1.0, 0
        while done < 1.0:
            h = min(h, 1.0 - done)
            if h < 1e-13:
                return None, count
            here = u_from + done * step_u
            J, F_u = self._rate_terms(q, here)
            singular = not self._smallest(J) >= SINGULAR
            prediction = q
            if not singular:
                tangent = np.linalg.solve(J, -(F_u @ step_u))
                prediction = q + h * tangent
                change = float(np.max(np.abs(h * tangent) * columns))
                if change > MAX_CHANGE:
                    h *= 0.9 * MAX_CHANGE / change
                    continue
            else:
                change = MAX_CHANGE
            found, fixed, used = self._correct(prediction, u_from + (done + h) * step_u, tol, max_iter)
            count += used
            if fixed:
                found[angles] = _unwrap_to(found[angles], prediction[angles])
                if float(np.max(np.abs(found - prediction) * columns)) <= max(0.5 * change, 1e-6):
                    q, done, h = found, done + h, min(2 * h, 1.0)
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
        rows, columns = self._scales

        def orientation(k):
            det = np.linalg.det(self._J(q[k], u[k]) / rows[:, None] / columns[None, :])
            return 0.0 if not abs(det) > SINGULAR else np.sign(det)

        for path in paths:
            last, sign = path[0], orientation(path[0])
            for k in path[1:]:
                found, iterations[k] = self._advance(q[last], u[last], u[k], tol, max_iter)
                if found is None:
                    continue
                q[k] = found
                now = orientation(k)
                if sign and now and now != sign:
                    notes.append(f"the assemblies meet (a change point) between {self._where(u, last)} and "
                                 f"{self._where(u, k)}: the motion continues on the smooth one")
                last, sign = k, now or sign
        return q, iterations
