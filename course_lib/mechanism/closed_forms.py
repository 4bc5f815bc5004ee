"""Closed forms: the blocks solved in turn, each reduced where it can be by the course's half-angle route to
one quadratic whose two roots are the block's two assemblies, followed along a sweep.

**σ, the one assembly vocabulary.**  A block's two assemblies are told apart by σ = −sign(det J_b), J_b the
block's rows of the loops differentiated by its unknowns, both in the declared order.  σ does not depend on
how the block is reduced, so ``assembly=`` may name any unknown of the block.  For a dyad — two links
meeting at a joint, their far ends known — det J_b vanishes exactly where the links line up, and σ tells on
which side of the line through the far ends the joint lies: with the links' angles θ_a, θ_b as its unknowns
(in that order), σ = +1 where the joint lies left of the directed line from θ_a's far end to θ_b's, however
the loop is written.  The course's machines: the four-bar's open
assembly (B left of the line A → O4) is σ = +1, crossed −1; the five-bar's arms up (P3 left of the line
P4 → P2, the larger Y3 while P2 is right of P4) is σ = +1, arms down −1.

One room of :class:`~course_lib.mechanism.Mechanism`, which is all of them together.
"""

from __future__ import annotations

import itertools
from collections.abc import Mapping

import numpy as np
import sympy as sp

from ..errors import (
    InvalidArgumentError,
    InvalidGeometryError,
)
from ..planar import scalar_or_array
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
        """Per block, the compiled (a, b, c), second-unknown and det J_b functions (J_b: the block's rows
        and unknowns of J, as declared; σ = −sign(det J_b)); None unless every block reduces."""
        forms = self._structure["forms"]
        if any(form is None for form in forms):
            return None
        compiled, J = [], self.equations.jacobian(self.unknowns)
        for form, (rows, columns) in zip(forms, self._structure["blocks"], strict=True):
            second = None
            if form.second is not None:
                second = self._compile(list(form.second[1:]), self.unknowns, self.inputs)
            linear = form.kind == "length" and form.quadratic[0] == 0
            orientation = self._compile([J.extract(rows, columns).det()], self.unknowns, self.inputs)
            compiled.append((self._compile(list(form.quadratic), self.unknowns, self.inputs), second, linear,
                             orientation))
        return compiled

    def _block_of(self) -> dict[str, str]:
        """Each unknown of a closed-form block (by name) → the name that keys its block internally (the
        block's first unknown as the half-angle route orders it)."""
        if self._closed_fns is None:
            return {}
        return {s.name: form.unknowns[0].name
                for form, (_, _, linear, _) in zip(self._structure["forms"], self._closed_fns, strict=True)
                if not linear for s in form.unknowns}

    def _assembly_at(self, position: Mapping, inputs: Mapping, shape) -> dict[str, np.ndarray] | None:
        """σ = −sign(det J_b) of each closed-form block at values found another way (a machine's own
        closed form), keyed like ``Motion.assembly``: every unknown of a block → its σ (shape ``shape``; 0
        where J_b is singular or the position not found); None where some block has no closed form."""
        if self._closed_fns is None:
            return None
        q, u, found = self._flat(position, inputs, shape)
        out = {}
        with np.errstate(all="ignore"):
            for form, fns in zip(self._structure["forms"], self._closed_fns, strict=True):
                if fns[2]:  # a linear block: one solution, no σ
                    continue
                det = fns[3](self._values, q, u)[0]
                sigma = np.where(found, -np.sign(det), 0).astype(int).reshape(shape)
                out.update({s.name: scalar_or_array(sigma) for s in form.unknowns})
        return {s.name: out[s.name] for s in self.unknowns if s.name in out}

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
        """``solve``'s ``assembly``: σ = ±1 by the name (or symbol) of any unknown of a block."""
        if assembly is None:
            return {}
        keys = self._block_of()
        if not isinstance(assembly, Mapping) or not closed:
            raise InvalidGeometryError(f"assembly must map an unknown of each closed-form block "
                                       f"({sorted(keys) or 'none here: give a guess instead'}) to σ = +1 or "
                                       f"−1; got assembly={assembly!r}")
        chosen = {}
        for key, value in assembly.items():
            name = getattr(key, "name", key)
            if not isinstance(name, str) or name not in keys or isinstance(value, bool | np.bool_) or not (
                    isinstance(value, int | float | np.integer | np.floating) and value in (1, -1)):
                raise InvalidGeometryError(f"assembly must map unknowns of the closed-form blocks "
                                           f"({sorted(keys)}) to σ = +1 or −1; "
                                           f"got assembly={dict(assembly)!r}")
            block = keys[name]
            if chosen.get(block, int(value)) != int(value):
                raise InvalidGeometryError(f"assembly gives two σ for one block ({name} and another unknown "
                                           f"of its block); got assembly={dict(assembly)!r}")
            chosen[block] = int(value)
        return chosen

    def assembly_sigma(self, assembly, aliases: Mapping[str, Mapping[str, int]] | None = None
                       ) -> dict[str, int]:
        """σ of each closed-form block that ``assembly`` chooses, keyed by every unknown of the block: a
        mapping of any unknown of a block (name or symbol) to σ = ±1, or one of a machine's ``aliases``
        (name → such a mapping, e.g. the four-bar's ``"open"`` → ``{"theta4": +1}``).

        >>> th2, th3, th4 = sp.symbols("theta2 theta3 theta4")
        >>> loop = sp.Matrix([0.06*sp.cos(th2) + 0.18*sp.cos(th3) - 0.12*sp.cos(th4) - 0.2,
        ...                   0.06*sp.sin(th2) + 0.18*sp.sin(th3) - 0.12*sp.sin(th4)])
        >>> wiper = Mechanism([loop], [th3, th4], [th2])
        >>> wiper.assembly_sigma({"theta3": -1}), wiper.assembly_sigma("open", {"open": {"theta4": 1}})
        ({'theta3': -1, 'theta4': -1}, {'theta3': 1, 'theta4': 1})
        """
        aliases = {} if aliases is None else aliases
        if isinstance(assembly, str):
            if assembly not in aliases:
                raise InvalidGeometryError(f"assembly must be one of {list(aliases)} or map an unknown of a "
                                           f"block to σ = +1 or −1; got assembly={assembly!r}")
            assembly = aliases[assembly]
        chosen = self._assembly(assembly, self._closed_fns is not None)
        blocks = self._block_of()
        return {s.name: chosen[blocks[s.name]] for s in self.unknowns
                if s.name in blocks and blocks[s.name] in chosen}

    def assembly_named(self, assembly, aliases: Mapping[str, Mapping[str, int]], older: str, default: str,
                       keyword: str = "branch") -> str:
        """A machine's assembly by its own name: ``assembly`` (one of ``aliases``, or σ by any unknown, read
        by :meth:`assembly_sigma`) turned into the alias it is, or ``older`` (the value of the machine's older
        ``keyword``, whose default is ``default``) when ``assembly`` is None; the two disagreeing is refused.

        >>> th2, th3, th4 = sp.symbols("theta2 theta3 theta4")
        >>> loop = sp.Matrix([0.06*sp.cos(th2) + 0.18*sp.cos(th3) - 0.12*sp.cos(th4) - 0.2,
        ...                   0.06*sp.sin(th2) + 0.18*sp.sin(th3) - 0.12*sp.sin(th4)])
        >>> names = {"open": {"theta4": 1}, "crossed": {"theta4": -1}}
        >>> Mechanism([loop], [th3, th4], [th2]).assembly_named({"theta3": -1}, names, "open", "open")
        'crossed'
        """
        if assembly is None:
            return older
        sigma = self.assembly_sigma(assembly, aliases)
        chosen = next(name for name, sigmas in aliases.items()
                      if all(sigma.get(key, value) == value for key, value in sigmas.items()))
        if older != default and older != chosen:
            raise InvalidArgumentError(f"{keyword} and assembly disagree: give one; got {keyword}={older!r}, "
                                       f"assembly={assembly!r}")
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
        for form, (coefficients, second, linear, orientation) in zip(structure["forms"], self._closed_fns,
                                                                     strict=True):
            first = self.unknowns.index(form.unknowns[0])
            a, b, c = coefficients(self._values, q, u, known=known)
            if linear:
                q[:, first] = -c / b
            else:
                plus, minus, level = self._roots(a, b, c, form.kind)
                # σ of the root +√Δ: −sign(det J_b) there (the other root's is the opposite)
                at_plus = q.copy()
                at_plus[:, first] = plus
                if form.second is not None:
                    at_plus[:, self.unknowns.index(form.unknowns[1])] = self._second(form, second, at_plus, u)
                side = -np.sign(orientation(self._values, np.where(np.isfinite(at_plus), at_plus, 0.0), u)[0])
                side = np.where(side == 0, 1.0, side)
                name = form.unknowns[0].name
                wanted = (chosen or {}).get(name)
                if wanted is None:
                    wanted = self._pick(plus, minus, paths, target, first, side)
                root = wanted * side  # +1: the root +√Δ, −1: the other
                self._follow(root, plus, minus, level, paths, u, first, notes)
                q[:, first] = np.where(root > 0, plus, minus)
                sigmas[name] = (root * side).astype(int)
            if form.second is not None:
                q[:, self.unknowns.index(form.unknowns[1])] = self._second(form, second, q, u, known)
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

    def _second(self, form, second, q, u, known=None) -> np.ndarray:
        """The block's second unknown from its first (already in ``q``)."""
        values = second(self._values, q, u, known=known)
        return np.arctan2(values[1], values[0]) if form.second[0] == "angle" else values[0]

    def _pick(self, plus, minus, paths, target, first, side) -> int:
        """σ at the first instant (along the paths) where the two roots differ: the one nearer ``target``
        (``side``: the σ of the root +√Δ per instant)."""
        if target is None:
            return 1
        for k in itertools.chain(*paths):
            both = np.array([plus[k], minus[k]])
            if np.isfinite(both).all() and self._distance(both[:1, None], both[1:, None], [0]) > 1e-7:
                size = self._scales[1][first]
                gaps = np.abs(both - target[first])
                if self.unknowns[first] in self._structure["angles"]:
                    gaps = np.abs(_unwrap_to(both - target[first], 0.0))
                return int((1 if gaps[0] * size <= gaps[1] * size else -1) * side[k])
        return 1

    def _follow(self, root, plus, minus, level, paths, u, first, notes) -> None:
        """Swap the root (``root``: +1 the root +√Δ, −1 the other, per instant) where the two assemblies
        meet between instants (a change point): there the other root continues the motion smoothly (a
        secant from the two instants before predicts it), and σ changes."""
        if u.shape[1] > 1:  # several inputs: no order of neighbours to follow; each instant keeps its σ
            return
        name, is_angle_ = self.unknowns[first].name, self.unknowns[first] in self._structure["angles"]
        for path in paths:
            for _ in range(64):
                if len(path) < 3:
                    break
                chosen = np.where(root[path] > 0, plus[path], minus[path])
                other = np.where(root[path] > 0, minus[path], plus[path])
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
                root[path[k:]] *= -1
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
