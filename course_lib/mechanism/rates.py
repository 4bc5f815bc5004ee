"""Rates: q̇ and q̈ at known positions, J·q̇ = −F_u·u̇ and J·q̈ = −(the rest of d²F/dt²), block by block.

One room of :class:`~course_lib.mechanism.Mechanism`, which is all of them together.
"""

from __future__ import annotations

from collections.abc import Mapping

import numpy as np

from ..errors import (
    InvalidGeometryError,
)
from ..newton import (
    LinearStack,
)
from .compiled import _matrix, _rows
from .declaration import _broadcast
from .singular import SINGULAR


class Rates:
    """Velocities and accelerations at known positions, by linear solves block by block."""

    def _unit_rows(self, J: np.ndarray):
        """J, or J̃ = J with rows and columns divided by their typical sizes where those are extreme (lengths
        of 1e±50 and beyond, whose determinants would overflow or underflow), and those sizes (or None): the
        solve is then J̃·(columns·x) = b / rows."""
        if not self._extreme_scales():
            return J, None
        rows, columns = self._scales
        return J / rows[:, None] / columns[None, :], (rows, columns)

    def _extreme_scales(self) -> bool:
        """Whether some row or column of J has a typical size beyond 1e±50 (its determinants would overflow
        or underflow): then the rates are solved on J̃."""
        sizes = np.r_[self._scales]
        return not ((sizes >= 1e-50) & (sizes <= 1e50)).all()

    def _fused(self, q, u, u_rate, u_acc, known=None, into=None):
        """J (N, n, n), q̇ and q̈ (n, N: a row per unknown) in one pass (:attr:`_fused_rate_fn`: Cramer's
        rule per block, as :meth:`_rates` solves blocks of one or two unknowns), or None where that pass
        does not apply (a block of three or more unknowns, or lengths so extreme that :meth:`_unit_rows`
        scales J); NaN and inf where J is singular, which the caller masks.  ``into``: (q̇, q̈), two
        (n, N) arrays to write them in (the caller's own rows)."""
        fused = self._fused_rate_fn
        if fused is None or self._extreme_scales():
            return None
        n = len(self.unknowns)
        if into is None:
            terms = fused(self._values, q, u, u_rate, u_acc, known=known, same_point=True)
            return _matrix(terms, 0, n, n), terms[n * n:n * n + n], terms[n * n + n:]
        J = np.empty((n * n, len(q)))
        fused(self._values, q, u, u_rate, u_acc, known=known, same_point=True, into=[*J, *into[0], *into[1]])
        return _matrix(J, 0, n, n), *into

    def _block_stacks(self, J: np.ndarray) -> list:
        """Per block of a stack J (N, n, n): its rows, columns, the columns solved before it, its diagonal
        block prepared for solving (:class:`LinearStack`) and the coupling to the earlier columns."""
        blocks = self._structure["blocks"]
        if len(blocks) == 1:
            return [(None, None, [], LinearStack(J), None)]
        entries = J.transpose(1, 2, 0)  # (n, n, N): contiguous for the compiled terms' J
        stacks, done = [], []
        for rows, columns in blocks:
            block = np.ascontiguousarray(entries[np.ix_(rows, columns)]).transpose(2, 0, 1)
            coupling = J[:, rows][:, :, done] if done else None
            stacks.append((rows, columns, done, LinearStack(block), coupling))
            done = done + list(columns)
        return stacks

    def _solve_blocks(self, J: np.ndarray, b: np.ndarray, stacks: list | None = None) -> np.ndarray:
        """x (N, n) with J·x = b for a stack J (N, n, n), block by block (forward substitution);
        ``stacks``: :meth:`_block_stacks` of J, when already prepared."""
        stacks = self._block_stacks(J) if stacks is None else stacks
        if len(stacks) == 1:
            return stacks[0][3].solve(b)
        x = np.empty(b.shape)
        for rows, columns, done, stack, coupling in stacks:
            rhs = b[:, rows]
            if done:
                rhs = rhs - np.einsum("nij,nj->ni", coupling, x[:, done])
            x[:, columns] = stack.solve(rhs)
        return x

    def unknown_rates(self, q, u, u_rate, u_acceleration=None, *, trig: Mapping | None = None, singular=None):
        """q̇, q̈ (None without ``u_acceleration``) and the singular mask at known positions, by J·q̇ =
        −F_u·u̇, J·q̈ = −(the rest of d²F/dt²); NaN where singular (σ_min(J̃) < SINGULAR, see
        :meth:`smallest_singular_value`).  ``q`` (..., n), the others (..., m); ``trig``: {name: (cos, sin)}
        already computed; ``singular``: the caller's own mask.

        >>> th, x = sp.symbols("theta x")
        >>> [a.tolist() for a in Mechanism([x**2 - th], [x], [th]).unknown_rates([2.0], [4.0], [1.0], [0.0])]
        [[0.25], [-0.03125], False]
        """
        names = dict(q=q, u=u, u_rate=u_rate)
        if u_acceleration is not None:
            names["u_acceleration"] = u_acceleration
        arrays = self._checked(**names)
        twin = self._twin()
        if twin is not None:  # lengths far from unit size: solved in the twin's units (see .scaling)
            units = twin._units
            scaled = [a / (units.q if k == 0 else units.u) for k, a in enumerate(arrays)]
            q_rate, q_acc, singular = twin.unknown_rates(*scaled[:3], *scaled[3:], trig=trig,
                                                         singular=singular)
            return q_rate * units.q, None if q_acc is None else q_acc * units.q, singular
        shape, arrays = _rows(*arrays)
        q, u, u_rate = arrays[:3]
        if trig is not None and not isinstance(trig, Mapping):
            raise InvalidGeometryError(f"trig must map names to (cos, sin) pairs; got {trig!r}")
        known = {(name, func): _broadcast(value, shape).ravel() for name, pair in (trig or {}).items()
                 for func, value in zip(("cos", "sin"), pair, strict=True)}
        J, F_u = self._rate_terms(q, u, known, same_point=True)
        if singular is None:
            singular = ~(self._smallest(J) >= SINGULAR)
        else:
            singular = _broadcast(np.asarray(singular, dtype=bool), shape).ravel()
        q_rate, q_acc, _ = self._rates(q, u, u_rate, arrays[3] if u_acceleration is not None else None,
                                       singular, (J, F_u), known)
        q_acc = None if q_acc is None else q_acc.reshape(shape + q_acc.shape[-1:])
        return q_rate.reshape(shape + q_rate.shape[-1:]), q_acc, singular.reshape(shape)

    def rates(self, q, u, u_rate, u_acceleration=None, *, trig: Mapping | None = None, singular=None):
        """The older name of :meth:`unknown_rates` (``rates`` is the inputs' rates given to ``solve``)."""
        return self.unknown_rates(q, u, u_rate, u_acceleration, trig=trig, singular=singular)

    def _rates(self, q, u, u_rate, u_acc, singular, terms, known=None
               ) -> tuple[np.ndarray, np.ndarray | None, np.ndarray]:
        """q̇ and q̈ (N, n; q̈ None without ``u_acc``) at solved positions from (J, F_u) there, NaN where
        ``singular`` (``known``: the cos and sin already computed at q and u, see _compile)."""
        J, F_u = terms
        by_rows = self._rates_by_rows(q, u, u_rate, u_acc, singular, J, F_u, known)
        if by_rows is not None:
            return by_rows
        J, unit = self._unit_rows(J)
        rows, columns = unit or (1.0, 1.0)
        any_singular = singular.any()
        if any_singular:
            J = np.where(singular[:, None, None], np.eye(len(self.unknowns)), J)
        stacks = self._block_stacks(J)
        q_rate = self._solve_blocks(J, np.einsum("nij,nj->ni", F_u, -u_rate) / rows, stacks) / columns
        q_acc = None
        if u_acc is not None:
            q_acc = self._solve_blocks(J, self._rhs(q, q_rate, u, u_rate, u_acc, known) / rows,
                                       stacks) / columns
        if any_singular:
            q_rate[singular] = np.nan
            if q_acc is not None:
                q_acc[singular] = np.nan
        return q_rate, q_acc, singular

    def _rates_by_rows(self, q, u, u_rate, u_acc, singular, J, F_u, known=None):
        """:meth:`_rates` with every array one row per entry or unknown ((N,) each, contiguous where J's
        compiled rows are): the same operations on the same values, in the same order — b = 0 + Σ F_u·(−u̇)
        and each block's right-hand side less 0 + Σ (coupling)·(earlier rates) as ``einsum`` sums them from 0,
        Cramer's rule as :class:`LinearStack` — for one input and blocks of one or two unknowns, each after at
        most two earlier ones (None elsewhere, where :meth:`_rates` solves as it does)."""
        blocks, n = self._structure["blocks"], len(self.unknowns)
        if (F_u.shape[-1] != 1 or self._extreme_scales() or any(len(c) > 2 for _, c in blocks)
                or any(len(rows) != len(c) for rows, c in blocks) or J.ndim != 3):
            return None
        done, order = [], []
        for rows, columns in blocks:
            if len(done) > 2:
                return None
            order.append((rows, columns, list(done)))
            done += list(columns)
        entries = J.transpose(1, 2, 0)  # (n, n, N): rows of the compiled terms
        any_singular = bool(singular.any())
        eye = np.eye(n)

        def entry(i, j):
            return np.where(singular, eye[i, j], entries[i, j]) if any_singular else entries[i, j]

        stacks = []
        for rows, columns, earlier in order:
            A = [[entry(i, j) for j in columns] for i in rows]
            det = A[0][0] if len(rows) == 1 else A[0][0] * A[1][1] - A[0][1] * A[1][0]
            coupling = [[entry(i, j) for j in earlier] for i in rows]
            stacks.append((rows, columns, earlier, A, det, coupling))

        def solve(b):  # b: one row (N,) per equation → x (n, N)
            x = np.empty((n, len(J)))
            for rows, columns, earlier, A, det, coupling in stacks:
                rhs = [b[i] for i in rows]
                if earlier:
                    for k, row in enumerate(coupling):
                        total = row[0] * x[earlier[0]]
                        for c, d in zip(row[1:], earlier[1:], strict=True):
                            total += c * x[d]
                        total += 0.0
                        rhs[k] = rhs[k] - total
                if len(rows) == 1:
                    x[columns[0]] = rhs[0] / det
                else:
                    x[columns[0]] = (A[1][1] * rhs[0] - A[0][1] * rhs[1]) / det
                    x[columns[1]] = (A[0][0] * rhs[1] - A[1][0] * rhs[0]) / det
            return x

        with np.errstate(all="ignore"):
            minus_rate = -u_rate[:, 0]
            b = []
            for i in range(n):
                row = F_u[:, i, 0] * minus_rate
                row += 0.0
                b.append(row)
            q_rate = solve(b)
            if any_singular:
                q_rate[:, singular] = np.nan
            q_acc = None
            if u_acc is not None:
                rest = self._rhs(q, q_rate.T, u, u_rate, u_acc, known)
                q_acc = solve([rest[:, i] for i in range(n)])
                if any_singular:
                    q_acc[:, singular] = np.nan
        return q_rate.T, None if q_acc is None else q_acc.T, singular
