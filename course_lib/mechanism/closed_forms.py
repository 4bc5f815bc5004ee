"""Closed forms: the blocks solved in turn, each reduced where it can be by the course's half-angle route to
one quadratic whose two roots are the block's two assemblies (σ = ±1), followed along a sweep.

One room of :class:`~course_lib.mechanism.Mechanism`, which is all of them together.
"""

from __future__ import annotations

import itertools
from collections.abc import Mapping

import numpy as np
import sympy as sp

from ..errors import (
    InvalidGeometryError,
)
from ..symbolic import LoopForm, is_angle, reduce_loop
from .continuation import MAX_CHANGE, _unwrap_to
from .declaration import _derived

#: A closed-form or continued position is accepted where |F_i| / (typical size of row i) stays below this.
RESIDUAL = 1e-8


class ClosedForms:
    """The blocks, their closed forms by the half-angle route, and each block's σ along a sweep."""

    @_derived
    def _structure(self) -> dict:
        """The blocks solved in turn (rows, columns), the angle unknowns, and each block's closed form
        (a :class:`~course_lib.symbolic.LoopForm`, or None where Newton solves it)."""
        n = len(self.unknowns)
        column = {s: j for j, s in enumerate(self.unknowns)}
        involves = [{column[s] for s in row.free_symbols if s in column} for row in self.equations]
        angles = {s for s in self.unknowns if all(is_angle(row, s) for row in self.equations if row.has(s))}
        remaining, solved, blocks = list(range(n)), set(), []

        def open_columns(rows):
            return set().union(*(involves[i] for i in rows)) - solved

        while remaining:
            whole = [g for g in self._loops if set(g) <= set(remaining)]
            choices = ([g for g in whole if len(open_columns(g)) == len(g) <= 2]
                       + [[i] for i in remaining if len(open_columns([i])) == 1]
                       + [list(p) for p in itertools.combinations(remaining, 2) if len(open_columns(p)) == 2]
                       + [g for g in whole if len(open_columns(g)) == len(g)])
            rows = choices[0] if choices else list(remaining)
            columns = sorted(open_columns(rows))
            if len(columns) != len(rows):
                rows, columns = list(remaining), sorted(set(range(n)) - solved)
            blocks.append((rows, columns))
            solved |= set(columns)
            remaining = [i for i in remaining if i not in rows]
        forms = []
        for rows, columns in blocks:
            form = None
            if len(columns) <= 2:
                try:
                    form = reduce_loop([self.equations[i] for i in rows], [self.unknowns[j] for j in columns],
                                       angles)
                except (ValueError, TypeError, NotImplementedError, ZeroDivisionError, sp.PolynomialError):
                    form = None
            forms.append(form)
        return {"blocks": blocks, "angles": angles, "forms": forms}

    @property
    def closed_forms(self) -> list[LoopForm | None]:
        """Each block's closed form, derived from the declaration by the half-angle route (None where a
        block does not reduce and Newton solves it); ``quadratic`` holds its (a, b, c).

        >>> th2, th3, th4 = sp.symbols("theta2 theta3 theta4")
        >>> l1, l2, l3, l4 = sp.symbols("l1:5", positive=True)
        >>> loop = sp.Matrix([l2*sp.cos(th2) + l3*sp.cos(th3) - l4*sp.cos(th4) - l1,
        ...                   l2*sp.sin(th2) + l3*sp.sin(th3) - l4*sp.sin(th4)])
        >>> form, = Mechanism([loop], [th3, th4], [th2], {l1: 0.2, l2: 0.06, l3: 0.18, l4: 0.12}).closed_forms
        >>> form.unknowns, form.quadratic[1]
        ((theta4, theta3), -4*l2*l4*sin(theta2))
        """
        return list(self._structure["forms"])

    @_derived
    def _closed_fns(self) -> list | None:
        """Per block, the compiled (a, b, c) and second-unknown functions; None unless every block reduces."""
        forms = self._structure["forms"]
        if any(form is None for form in forms):
            return None
        compiled = []
        for form in forms:
            second = None
            if form.second is not None:
                second = self._compile(list(form.second[1:]), self.unknowns, self.inputs)
            linear = form.kind == "length" and form.quadratic[0] == 0
            compiled.append((self._compile(list(form.quadratic), self.unknowns, self.inputs), second, linear))
        return compiled

    @staticmethod
    def _roots(a, b, c, kind):
        """The roots σ = +1 and −1 of a·v² + b·v + c = 0 (v = tan(θ/2) → θ for an angle), each from the
        better-conditioned of (−b + σ√Δ)/(2a) and 2c/(−b − σ√Δ), NaN where Δ < 0 beyond rounding; and Δ over
        its scale: (root +1, root −1, Δ / scale)."""
        discriminant = b * b - 4 * a * c
        # for an angle, (a, b, c) = (C − A, 2B, C + A) of A cos θ + B sin θ + C:
        # Δ ≤ b² + (a − c)² = 4(A² + B²)
        scale = b * b + ((a - c) ** 2 if kind == "angle" else np.abs(4 * a * c))
        bad = ~(discriminant >= -1e-12 * scale)
        root = np.sqrt(np.maximum(discriminant, 0.0))
        two_a, two_c = 2 * a, 2 * c
        size_a, size_c = np.abs(two_a), np.abs(two_c)
        out = []
        for y1, x2 in ((-b + root, -b - root), (-b - root, -b + root)):
            first = np.abs(y1) + size_a >= size_c + np.abs(x2)
            y, x = np.where(first, y1, two_c), np.where(first, two_a, x2)
            wrong = bad | ((np.abs(y) + np.abs(x)) == 0)
            value = 2 * np.arctan2(y, x) if kind == "angle" else y / x
            out.append(np.where(wrong, np.nan, value))
        return out[0], out[1], np.where(scale > 0, discriminant / scale, 0.0)

    def _assembly(self, assembly: Mapping | None, closed: bool) -> dict[str, int]:
        """``solve``'s ``assembly``: σ = ±1 by the name (or symbol) of a block's first unknown."""
        if assembly is None:
            return {}
        firsts = [form.unknowns[0].name for form in self._structure["forms"] if form is not None and closed]
        if not isinstance(assembly, Mapping) or not closed:
            raise InvalidGeometryError(f"assembly must map the first unknown of each closed-form block "
                                       f"({firsts or 'none here: give a guess instead'}) to σ = +1 or −1; "
                                       f"got assembly={assembly!r}")
        chosen = {}
        for key, value in assembly.items():
            name = getattr(key, "name", key)
            if name not in firsts or isinstance(value, bool) or value not in (1, -1):
                raise InvalidGeometryError(f"assembly must map one of {firsts} to σ = +1 or −1; got "
                                           f"assembly={dict(assembly)!r}")
            chosen[name] = int(value)
        return chosen

    def _closed(self, u, paths, target, tol, max_iter, notes, chosen=None, known=None
                ) -> tuple[np.ndarray, np.ndarray, dict, dict | None]:
        """Positions (N, n) from the closed forms, each block's σ picked at the first instant from
        ``target`` (the Newton solution, or the guess) and kept along the paths except where the two
        assemblies meet (a change point, reported in ``notes``); then cross-checked by the residual.
        ``known``: the inputs' cos and sin (see _compile), shared; also returned: those of the positions
        too, where every position is found and none was corrected (else None)."""
        known = {} if known is None else known
        N, n = len(u), len(self.unknowns)
        q, sigmas = np.full((N, n), np.nan), {}
        structure = self._structure
        for form, (coefficients, second, linear) in zip(structure["forms"], self._closed_fns, strict=True):
            first = self.unknowns.index(form.unknowns[0])
            a, b, c = coefficients(self._values, q, u, known=known)
            if linear:
                q[:, first] = -c / b
            else:
                plus, minus, level = self._roots(a, b, c, form.kind)
                name = form.unknowns[0].name
                picked = (chosen or {}).get(name) or self._pick(plus, minus, paths, target, first)
                sigma = np.full(N, picked)
                self._follow(sigma, plus, minus, level, paths, u, first, notes)
                q[:, first] = np.where(sigma > 0, plus, minus)
                sigmas[form.unknowns[0].name] = sigma
            if form.second is not None:
                other = self.unknowns.index(form.unknowns[1])
                values = second(self._values, q, u, known=known)
                q[:, other] = np.arctan2(values[1], values[0]) if form.second[0] == "angle" else values[0]
        self._continuous(q, paths, target)
        iterations = np.zeros(N, int)
        rows = self._scales[0]
        finite = np.isfinite(q).all(axis=1)
        everywhere = bool(finite.all())
        at_q = dict(known)
        at = q if everywhere else np.where(finite[:, None], q, 0.0)
        residual = np.abs(self._F(at, u, at_q, same_point=True)) / rows
        doubt = np.flatnonzero(finite & ~(residual.max(axis=1) <= RESIDUAL))
        for k in doubt:  # the cross-check: Newton from the closed form, kept only on the same assembly
            polished, fixed, count = self._correct(q[k], u[k], tol, max_iter)
            iterations[k] = count
            q[k] = polished if fixed and self._distance(polished, q[k]) <= MAX_CHANGE else np.nan
        return q, iterations, sigmas, at_q if everywhere and not len(doubt) else None

    def _pick(self, plus, minus, paths, target, first) -> int:
        """σ at the first instant (along the paths) where the two roots differ: the one nearer ``target``."""
        if target is None:
            return 1
        for k in itertools.chain(*paths):
            both = np.array([plus[k], minus[k]])
            if np.isfinite(both).all() and self._distance(both[:1, None], both[1:, None], [0]) > 1e-7:
                size = self._scales[1][first]
                gaps = np.abs(both - target[first])
                if self.unknowns[first] in self._structure["angles"]:
                    gaps = np.abs(_unwrap_to(both - target[first], 0.0))
                return 1 if gaps[0] * size <= gaps[1] * size else -1
        return 1

    def _follow(self, sigma, plus, minus, level, paths, u, first, notes) -> None:
        """Swap σ where the two assemblies meet between instants (a change point): there the other root
        continues the motion smoothly (a secant from the two instants before predicts it)."""
        name, is_angle_ = self.unknowns[first].name, self.unknowns[first] in self._structure["angles"]
        for path in paths:
            for _ in range(64):
                if len(path) < 3:
                    break
                chosen = np.where(sigma[path] > 0, plus[path], minus[path])
                other = np.where(sigma[path] > 0, minus[path], plus[path])
                steps = np.linalg.norm(np.diff(u[path], axis=0), axis=1)
                ratio = np.where(steps[:-1] > 0, steps[1:] / np.where(steps[:-1] > 0, steps[:-1], 1.0), 0.0)
                back = chosen[1:-1] - chosen[:-2]
                if is_angle_:
                    back = _unwrap_to(back, 0.0)
                predicted = chosen[1:-1] + back * ratio

                def gap(values, predicted=predicted):
                    d = values - predicted
                    return np.abs(_unwrap_to(d, 0.0) if is_angle_ else d)

                same, swapped = gap(chosen[2:]), gap(other[2:])
                low = np.minimum(level[path][1:-1], level[path][2:])
                suspect = (swapped < 0.25 * same) & (same * self._scales[1][first] > 1e-6) & (low < 0.1)
                if not suspect.any():
                    break
                k = int(np.argmax(suspect)) + 2
                sigma[path[k:]] *= -1
                notes.append(f"the two assemblies of {name} meet (a change point) between "
                             f"{self._where(u, path[k - 1])} and {self._where(u, path[k])}: the motion "
                             "continues on the smooth one (σ swapped there)")

    def _continuous(self, q, paths, target) -> None:
        """Angles unwrapped along each path, the first instant's within π of ``target`` (if any)."""
        columns = [j for j, s in enumerate(self.unknowns)
                   if s in self._structure["angles"] and np.isfinite(q[0, j])]
        if not columns:
            return
        if target is not None:
            q[0, columns] = _unwrap_to(q[0, columns], target[columns])
        for path in paths:
            ordered = len(path) > 1 and path[0] == 0 and path[-1] == len(path) - 1 \
                and bool((np.diff(path) == 1).all())
            rows = slice(0, len(path)) if ordered else path
            values = q[rows][:, columns]
            finite = np.isfinite(values).all(axis=1)
            if not finite[0] or finite.sum() < 2:
                continue
            if not finite.all():
                rows, values = path[finite], values[finite]
            # each step within π: whole turns taken off, counted along the path
            turns = np.cumsum(np.round(np.diff(values, axis=0) / (2 * np.pi)), axis=0)
            moved = (turns != 0).any(axis=0)
            for k in np.flatnonzero(moved):
                kept = values[1:, k] - 2 * np.pi * turns[:, k]
                if isinstance(rows, slice):
                    q[1:len(path), columns[k]] = kept
                else:
                    q[rows[1:], columns[k]] = kept
