"""The one singularity rule: J is singular where the smallest singular value of J̃ — J with each row and
column divided by its typical size at the declaration's generic point — is below ``SINGULAR``; near one
below ``NEAR_SINGULAR`` (the rates are large and sensitive there).

One room of :class:`~course_lib.mechanism.Mechanism`, which is all of them together.
"""

from __future__ import annotations

import numpy as np

from ..symbolic import is_angle
from ..thresholds import NEAR_SINGULAR, SINGULAR  # the numbers, with every other threshold

__all__ = ["NEAR_SINGULAR", "SINGULAR", "Singularity"]

def _rms(values: np.ndarray, axis) -> np.ndarray:
    """Root mean square over ``axis``, computed on values divided by their largest size (no overflow or
    underflow, at lengths from 1e-300 to 1e300 alike)."""
    peak = np.abs(values).max(axis=axis, keepdims=True)
    safe = np.where(peak > 0, peak, 1.0)
    return (safe * np.sqrt(((values / safe) ** 2).mean(axis=axis, keepdims=True))).squeeze(axis)


def _smallest_two(J: np.ndarray, rows: np.ndarray, columns: np.ndarray) -> np.ndarray:
    """σ_min of a stack of 2×2 J̃ = J with row i divided by ``rows[i]`` and column j by ``columns[j]``:
    |det J̃| / σ_max, σ_max² = (‖J̃‖²_F + √(‖J̃‖⁴_F − 4 det² J̃)) / 2, 0 where σ_max is 0 or not a number;
    each entry of J̃ divided by its row's size, then its column's, and the squares summed row by row, a
    stack's entries in place (the temporaries of a long sweep are the time, not the arithmetic)."""
    shape = J.shape[:-2]
    J = J.reshape(-1, 2, 2)
    with np.errstate(all="ignore"):
        a, b = np.divide(J[:, 0, 0], rows[0]), np.divide(J[:, 0, 1], rows[0])
        c, d = np.divide(J[:, 1, 0], rows[1]), np.divide(J[:, 1, 1], rows[1])
        a /= columns[0]
        b /= columns[1]
        c /= columns[0]
        d /= columns[1]
        frobenius, work = np.multiply(a, a), np.multiply(b, b)  # ‖J̃‖²_F = ((a² + b²) + c²) + d²
        frobenius += work
        frobenius += np.multiply(c, c, out=work)
        frobenius += np.multiply(d, d, out=work)
        det = np.multiply(a, d, out=a)  # det J̃ = ad − bc
        det -= np.multiply(b, c, out=work)
        largest = np.multiply(frobenius, frobenius, out=b)  # σ_max, in b
        largest -= np.multiply(4, np.multiply(det, det, out=c), out=c)
        np.maximum(largest, 0.0, out=largest)
        np.sqrt(largest, out=largest)
        largest += frobenius
        largest /= 2
        np.sqrt(largest, out=largest)
        smallest = np.abs(det, out=det)
        smallest /= largest
        if not (positive := largest > 0).all():
            smallest[~positive] = 0.0
    return smallest.reshape(shape)


class Singularity:
    """The one singularity rule: typical sizes at the generic point and σ_min(J̃)."""

    def _generic_jacobians(self) -> np.ndarray | None:
        """J at 24 generic configurations (angles in (−π, π], lengths of the parameters' typical size)."""
        if "generic" not in self._numeric:
            sizes = [abs(v) for v in self._values if v != 0.0]
            length = float(np.median(sizes)) if sizes else 1.0
            rng = np.random.default_rng(0)
            angles = self._structure["angles"] | {s for s in self.inputs if all(
                is_angle(row, s) for row in self.equations if row.has(s))}

            def sample(symbols):
                return np.column_stack([rng.uniform(-np.pi, np.pi, 24) if s in angles else
                                        length * rng.uniform(0.5, 2.0, 24) * rng.choice([-1, 1], 24)
                                        for s in symbols])

            q, u = sample(self.unknowns), sample(self.inputs)
            with np.errstate(all="ignore"):
                J = self.jacobian(q, u)
            J = J[np.isfinite(J).all(axis=(1, 2))]
            self._numeric["generic"] = J if len(J) else None
        return self._numeric["generic"]

    @property
    def _scales(self) -> tuple[np.ndarray, np.ndarray]:
        """Typical size of each row and column of J at the generic configurations (rows first)."""
        if "scales" not in self._numeric:
            J, n = self._generic_jacobians(), len(self.unknowns)
            if J is None:
                rows = columns = np.ones(n)
            else:
                units = self._column_units(J)
                J = J / units
                rows = _rms(J, (0, 2))
                rows = np.where(rows > 0, rows, 1.0)
                scaled = J / rows[:, None]
                columns = _rms(scaled, (0, 1))
                columns = np.where(columns > 0, columns, 1.0) * units
            self._numeric["scales"] = (rows, columns)
        return self._numeric["scales"]

    def _column_units(self, J: np.ndarray) -> np.ndarray:
        """A unit for each column of J: 1 for an angle, one typical length ℓ for every length — the ℓ of
        the least-squares fit log|J_ij| ≈ log d_i + log ℓ·[j a length] over the nonzero typical sizes.  A
        change of units multiplies row i of J by some d_i and the lengths' columns by 1/k: ℓ moves by k, so
        J divided by these units changes by whole rows only, which the row sizes take.  With angles alone
        or lengths alone every unit is 1 (then a change of units is such rows already)."""
        lengths = [j for j, s in enumerate(self.unknowns) if s not in self._structure["angles"]]
        units = np.ones(len(self.unknowns))
        if not lengths or len(lengths) == len(units):
            return units
        size = _rms(J, 0)
        i, j = np.nonzero(size > 0)
        fit = np.zeros((len(i), len(units) + 1))
        fit[np.arange(len(i)), i] = 1.0
        fit[:, -1] = np.isin(j, lengths)
        solution = np.linalg.lstsq(fit, np.log(size[i, j]), rcond=None)[0]
        units[lengths] = np.exp(solution[-1])
        return units

    def smallest_singular_value(self, q, u) -> np.ndarray:
        """σ_min(J̃) at positions ``q`` (..., n) and inputs ``u`` (..., m): J̃ is J with each row and column
        divided by its typical size at the declaration's generic point, so the test ignores units and a
        row vanishing as a whole counts.  J is singular where it is below ``SINGULAR``.

        >>> x, y, s = sp.symbols("x y s")
        >>> trammel = Mechanism([x**2 + y**2 - 1, x - s], [x, y], [s])
        >>> values = trammel.smallest_singular_value([[0.6, 0.8], [1.0, 0.0]], [[0.6], [1.0]])
        >>> [round(float(v), 3) for v in values]
        [0.798, 0.0]
        """
        q, u = self._checked(q=q, u=u)
        form, q, u = self._in_twin(q, u)  # lengths far from unit size: J in the twin's units (see .scaling)
        return form._smallest(form.jacobian(q, u))

    def is_singular(self, q, u) -> np.ndarray:
        """The one singularity rule: True where σ_min(J̃) < ``SINGULAR`` (see
        :meth:`smallest_singular_value`), or where J is not finite; ``q`` (..., n), ``u`` (..., m).

        >>> x, y, s = sp.symbols("x y s")
        >>> Mechanism([x**2 + y**2 - 1, x - s], [x, y], [s]).is_singular([[0.6, 0.8], [1.0, 0.0]],
        ...                                                               [[0.6], [1.0]]).tolist()
        [False, True]
        """
        return ~(self.smallest_singular_value(q, u) >= SINGULAR)

    def _below(self, J: np.ndarray, singular: np.ndarray, near: np.ndarray) -> None:
        """The rule at a stack J (N, n, n), into ``singular`` and ``near`` (N,): σ_min(J̃) < SINGULAR and
        σ_min(J̃) < NEAR_SINGULAR, σ_min computed (:meth:`_smallest`) only where the bound of
        :meth:`_settled` cannot settle them (n ≥ 2)."""
        n = J.shape[-1]
        if n >= 2 and J.ndim == 3 and len(J):
            settled = self._settled(J)
            singular[:] = False
            near[:] = False
            if settled.all():
                return
            where = np.flatnonzero(~settled)
            J = J[where]
        else:
            where = slice(None)
        smallest = self._smallest(J)
        singular[where] = ~(smallest >= SINGULAR)
        near[where] = ~(smallest >= NEAR_SINGULAR)

    def _settled(self, J: np.ndarray) -> np.ndarray:
        """Where a stack J (N, n, n), n ≥ 2, has σ_min(J̃) ≥ NEAR_SINGULAR proven by the lower bound
        |det J̃| / ‖J̃‖_F^(n−1) of :meth:`_smallest`, itself above NEAR_SINGULAR there: det² J̃ above
        (1 + 1e-9)·NEAR_SINGULAR²·‖J̃‖_F^(2(n−1)) with ‖J̃‖²_F ≤ 1e4 (J̃'s entries of order 1 by their
        scaling), so the rounding of either way of computing it (parts in 1e14 at most) cannot move it
        across NEAR_SINGULAR; :meth:`_smallest` decides elsewhere, as at every instant.  Entries row by
        row from the compiled terms' rows (each (N,) contiguous), det J̃ block by block as there."""
        rows, columns = self._scales
        n = J.shape[-1]
        entries = J.transpose(1, 2, 0)  # (n, n, N): each entry's values one after the other
        weight = 1 / np.outer(rows, columns)
        with np.errstate(all="ignore"):
            scaled = [[np.multiply(entries[i, j], weight[i, j]) for j in range(n)] for i in range(n)]
            size, work = np.zeros(len(J)), np.empty(len(J))
            for row in scaled:
                for entry in row:
                    size += np.multiply(entry, entry, out=work)
            det = None
            for block_rows, block_columns in self._structure["blocks"]:
                if len(block_rows) == 1:
                    part = scaled[block_rows[0]][block_columns[0]]
                elif len(block_rows) == 2:
                    (i, k), (j, m) = block_rows, block_columns
                    part = scaled[i][j] * scaled[k][m] - scaled[i][m] * scaled[k][j]
                else:
                    block = np.array([[scaled[i][j] for j in block_columns] for i in block_rows])
                    part = np.linalg.det(np.moveaxis(block, (0, 1), (-2, -1)))
                det = part if det is None else det * part
            det = det * det
            settled = size <= 1e4
            size **= n - 1
            size *= (1 + 1e-9) * NEAR_SINGULAR ** 2
            settled &= det > size
        return settled

    def _smallest(self, J: np.ndarray) -> np.ndarray:
        """σ_min(J̃) of a stack J (..., n, n): exact for n ≤ 2, else exact where a bound cannot settle it."""
        rows, columns = self._scales
        n = J.shape[-1]
        if n == 2:
            return _smallest_two(J, rows, columns)
        # entries first (n, n, ...): contiguous for the compiled terms' J, so each operation runs in one pass
        A = np.moveaxis(J, (-2, -1), (0, 1)) / rows[:, None].reshape((n, 1) + (1,) * (J.ndim - 2))
        A /= columns.reshape((1, n) + (1,) * (J.ndim - 2))
        with np.errstate(all="ignore"):
            if n == 1:
                return np.abs(A[0, 0])
            frobenius = (A * A).sum(axis=(0, 1))
            det = np.ones(A.shape[2:])
            for block_rows, block_columns in self._structure["blocks"]:
                block = A[np.ix_(block_rows, block_columns)]
                if len(block_rows) == 1:
                    det = det * block[0, 0]
                elif len(block_rows) == 2:
                    det = det * (block[0, 0] * block[1, 1] - block[0, 1] * block[1, 0])
                else:
                    det = det * np.linalg.det(np.moveaxis(block, (0, 1), (-2, -1)))
            smallest = np.array(np.abs(det) / np.sqrt(frobenius) ** (n - 1))  # a lower bound (an array)
            unsure = ~(smallest >= NEAR_SINGULAR) & np.isfinite(frobenius)
            if unsure.any():
                stacked = np.moveaxis(A, (0, 1), (-2, -1))
                smallest[unsure] = np.linalg.svd(stacked[unsure], compute_uv=False)[..., -1]
            return smallest

    def _smallest_where(self, position, inputs, shape) -> np.ndarray:
        """σ_min(J̃) (shape ``shape``) at the declared values by name (unknowns not finite taken as 0)."""
        q, u, _ = self._flat(position, inputs, shape)
        form, q, u = self._in_twin(q, u)  # lengths far from unit size: J in the twin's units (see .scaling)
        with np.errstate(all="ignore"):
            return form._smallest(form._J(q, u)).reshape(shape)
