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

import copy
import itertools
from collections.abc import Callable, Mapping
from dataclasses import dataclass
from types import MappingProxyType
from typing import TYPE_CHECKING

import numpy as np
import sympy as sp

from ..errors import (
    InvalidArgumentError,
    InvalidGeometryError,
)
from ..planar import scalar_or_array
from ..symbolic import LoopForm, is_angle, reduce_loop
from ..thresholds import CHANGE_LEVEL, LEVEL, RESIDUAL
from .compiled import _BLOCK, _finite_rows
from .continuation import MAX_CHANGE, _unwrap_to
from .declaration import _derived

if TYPE_CHECKING:
    from . import Mechanism

__all__ = ["LEVEL", "RESIDUAL", "ClosedForms", "KernelBlock"]


def _instants(value, count: int) -> np.ndarray:
    """A kernel's value as floats at ``count`` instants: its own array when it is one already (no view made),
    else broadcast (read-only); ValueError where it does not broadcast."""
    if type(value) is np.ndarray and value.dtype == np.float64 and value.shape == (count,):
        return value
    return np.broadcast_to(np.asarray(value, float), (count,))


@dataclass(frozen=True)
class KernelBlock:
    """A block with no closed form (Newton would solve it) that a registered kernel solves: its unknowns as
    declared.  It stands where a :class:`~course_lib.symbolic.LoopForm` stands for a block that reduces."""

    unknowns: tuple
    kind: str = "kernel"
    second: None = None
    quadratic: None = None


def _sigma(value, per_instant: bool):
    """σ = ±1 as an int, or (``per_instant``) an int8 array of ±1; None if ``value`` is neither."""
    if isinstance(value, bool | np.bool_):
        return None
    if isinstance(value, int | float | np.integer | np.floating):
        return int(value) if value in (1, -1) else None
    if not per_instant or isinstance(value, str | bytes | Mapping):
        return None
    try:
        array = np.asarray(value)
    except (TypeError, ValueError):
        return None
    if array.dtype.kind not in "iuf" or not np.isin(array, (1, -1)).all():
        return None
    return array.astype(np.int8)


def _linear(form) -> bool:
    """Whether a block's closed form is linear in its first unknown (one solution, no σ)."""
    return isinstance(form, LoopForm) and form.kind == "length" and form.quadratic[0] == 0


class ClosedForms:
    """The blocks, their closed forms by the half-angle route, and each block's σ along a sweep."""

    #: Registered kernels: a block's key (see ``_block_of``) → the solver the core calls for that block.
    _kernels: Mapping = MappingProxyType({})

    def with_kernel(self, unknown, kernel: Callable) -> Mechanism:
        """The same declaration with ``kernel`` registered as the solver of the block of ``unknown`` (its
        name or symbol): a hand-vectorised closed form the core calls instead of the one it derives (or,
        for a block with no closed form, instead of Newton), for speed, with everything else (σ, change
        points, angles kept continuous, rates, singularity, failures) the core's own.
        ``kernel(parameters, known, sigma)`` gets the parameters and the values already known (inputs, and
        unknowns of earlier blocks) by name, each (N,), and σ = ±1 (the meaning of
        :mod:`~course_lib.mechanism.closed_forms`, −sign(det J_b), on a block Newton would solve too); it
        returns the block's unknowns by name, each (N,), NaN where the block cannot close (and, if it has
        them at hand, their cos and sin and the inputs', keyed ``(name, "cos")``, ``(name, "sin")``: the
        rates then take them, where σ was named), and the level per instant, 0 where the two assemblies
        meet and < 0 where the block cannot close (for a half-angle quadratic, b² − 4ac over b² + (a − c)²).
        A kernel must agree with the derived closed form (or with Newton's solution, for a block with no
        closed form); test it.

        >>> x, s = sp.symbols("x s")
        >>> arc = Mechanism([sp.cos(x) - s], [x], [s])  # σ = −sign(∂F/∂x) = sign(sin x)
        >>> def kernel(parameters, known, sigma):
        ...     return {"x": sigma * np.arccos(known["s"])}, 1 - known["s"] ** 2
        >>> fast = arc.with_kernel("x", kernel)
        >>> [round(m.solve({s: 0.5}, assembly={x: sign}).position["x"], 6)
        ...  for m in (arc, fast) for sign in (1, -1)]
        [1.047198, -1.047198, 1.047198, -1.047198]
        """
        blocks = self._block_of(every=True)
        name = getattr(unknown, "name", unknown)
        if not isinstance(name, str) or name not in blocks:
            raise InvalidArgumentError(f"unknown must name an unknown of a block with two "
                                       f"assemblies ({sorted(blocks) or 'none here'}); "
                                       f"got unknown={unknown!r}")
        if not callable(kernel):
            raise InvalidArgumentError(f"kernel must be a function (parameters, known, sigma) → (values by "
                                       f"name, level); got kernel={kernel!r}")
        other = copy.copy(self)
        other._kernels = MappingProxyType({**self._kernels, blocks[name]: kernel})
        return other

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
    def _slots(self) -> list:
        """Each block's closed form, or a :class:`KernelBlock` of its unknowns where it has none (a block a
        kernel may solve)."""
        structure = self._structure
        return [form if form is not None else KernelBlock(tuple(self.unknowns[j] for j in columns))
                for form, (_, columns) in zip(structure["forms"], structure["blocks"], strict=True)]

    @property
    def _forms(self) -> list:
        """Each block's closed form, a :class:`KernelBlock` where a kernel solves a block with none, else
        None (Newton solves it)."""
        return [slot if isinstance(slot, LoopForm) or slot.unknowns[0].name in self._kernels else None
                for slot in self._slots]

    @property
    def _closed_fns(self) -> list | None:
        """Per block, the compiled (a, b, c), second-unknown and det J_b functions (J_b: the block's rows
        and unknowns of J, as declared; σ = −sign(det J_b)); None unless every block reduces or has a
        kernel (a block with a kernel and no closed form: (None, None, False, det J_b))."""
        if any(form is None for form in self._forms):
            return None
        return self._compiled_blocks

    @_derived
    def _compiled_blocks(self) -> list:
        """:attr:`_closed_fns` of every block, None in the place of a form where a block does not reduce."""
        compiled, J = [], self.equations.jacobian(self.unknowns)
        for form, (rows, columns) in zip(self._structure["forms"], self._structure["blocks"], strict=True):
            orientation = self._compile([J.extract(rows, columns).det()], self.unknowns, self.inputs)
            if form is None:
                compiled.append((None, None, False, orientation))
                continue
            second = None
            if form.second is not None:
                second = self._compile(list(form.second[1:]), self.unknowns, self.inputs)
            compiled.append((self._compile(list(form.quadratic), self.unknowns, self.inputs), second,
                             _linear(form), orientation))
        return compiled

    def _block_of(self, every: bool = False) -> dict[str, str]:
        """Each unknown of a block with two assemblies (by name) → the name that keys its block internally
        (the block's first unknown as the half-angle route orders it, or as declared for a block with no
        closed form): of the blocks ``solve`` chooses σ for (none unless every block reduces or has a
        kernel), or, with ``every``, of every block a kernel may be registered on."""
        if every:
            forms = self._slots
        elif self._closed_fns is None:
            return {}
        else:
            forms = self._forms
        return {s.name: form.unknowns[0].name for form in forms if not _linear(form) for s in form.unknowns}

    def _assembly_at(self, position: Mapping, inputs: Mapping, shape) -> dict[str, np.ndarray] | None:
        """σ = −sign(det J_b) of each closed-form block at values found another way (a machine's own
        closed form), keyed like ``Motion.assembly``: every unknown of a block → its σ (shape ``shape``; 0
        where J_b is singular or the position not found); None where some block has no closed form."""
        if self._closed_fns is None:
            return None
        q, u, found = self._flat(position, inputs, shape)
        on, q, u = self._in_twin(q, u)  # lengths far from unit size: det J_b in the twin's units (.scaling)
        out = {}
        with np.errstate(all="ignore"):
            for form, fns in zip(self._forms, self._closed_fns, strict=True):
                if fns[2]:  # a linear block: one solution, no σ
                    continue
                det = fns[3](on._values, q, u)[0]
                sigma = np.where(found, -np.sign(det), 0).astype(int).reshape(shape)
                out.update({s.name: scalar_or_array(sigma) for s in form.unknowns})
        return {s.name: out[s.name] for s in self.unknowns if s.name in out}

    @staticmethod
    def _roots(a, b, c, kind):
        """The roots σ = +1 and −1 of a·v² + b·v + c = 0 (v = tan(θ/2) → θ for an angle), each from the
        better-conditioned of (−b + σ√Δ)/(2a) and 2c/(−b − σ√Δ), NaN where Δ < 0 beyond rounding; and Δ over
        its scale: (root +1, root −1, Δ / scale)."""
        square_b = b * b
        discriminant = square_b - 4 * a * c
        # for an angle, (a, b, c) = (C − A, 2B, C + A) of A cos θ + B sin θ + C:
        # Δ ≤ b² + (a − c)² = 4(A² + B²)
        scale = square_b + ((a - c) ** 2 if kind == "angle" else np.abs(4 * a * c))
        bad = ~(discriminant >= -LEVEL * scale)
        root = np.sqrt(np.maximum(discriminant, 0.0))
        two_a, two_c = 2 * a, 2 * c
        size_a, size_c = np.abs(two_a), np.abs(two_c)
        minus_b = -b
        up, down = minus_b + root, minus_b - root  # −b + √Δ, −b − √Δ
        size_up, size_down = np.abs(up), np.abs(down)
        out = []
        for y1, x2, size_y1, size_x2 in ((up, down, size_up, size_down), (down, up, size_down, size_up)):
            size = size_y1 + size_a
            first = size >= size_c + size_x2
            if first.all():  # (−b ± √Δ)/(2a) at every instant: y and x as they are
                y, x = y1, two_a
            else:
                y, x = np.where(first, y1, two_c), np.where(first, two_a, x2)
                size = np.abs(y) + np.abs(x)
            wrong = size == 0
            wrong |= bad
            if kind == "angle":
                value = np.arctan2(y, x)
                value *= 2
            else:
                value = np.divide(y, x)
            if wrong.any():
                value[wrong] = np.nan
            out.append(value)
        # scale 0: b = 0 and a = c (an angle) or a·c = 0 (a length); the level 0 where a root remains (a
        # double one, or every v where every coefficient is 0: the position not determined), else −1
        positive = scale > 0
        if positive.all():
            return out[0], out[1], np.divide(discriminant, scale, out=discriminant)
        return out[0], out[1], np.where(positive, discriminant / np.where(positive, scale, 1.0),
                                        np.where((discriminant < 0) | ((a == 0) & (c != 0)), -1.0, 0.0))

    def _assembly(self, assembly: Mapping | None, closed: bool, per_instant: bool = False) -> dict:
        """``solve``'s ``assembly``: σ = ±1 by the name (or symbol) of any unknown of a block; with
        ``per_instant``, also an array of ±1 per instant (broadcast with the inputs by ``solve``)."""
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
            sigma = _sigma(value, per_instant)
            if not isinstance(name, str) or name not in keys or sigma is None:
                each = " (or an array of them, one per instant)" if per_instant else ""
                raise InvalidGeometryError(f"assembly must map unknowns of the closed-form blocks "
                                           f"({sorted(keys)}) to σ = +1 or −1{each}; "
                                           f"got assembly={dict(assembly)!r}"[:600])
            block = keys[name]
            if block in chosen and not np.array_equal(chosen[block], sigma):
                raise InvalidGeometryError(f"assembly gives two σ for one block ({name} and another unknown "
                                           f"of its block); got assembly={dict(assembly)!r}"[:600])
            chosen[block] = sigma
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

    def _closed(self, u, paths, target, tol, max_iter, notes, chosen=None, known=None, *, refine: int = 2,
                stop: int | None = None, outer: np.ndarray | None = None
                ) -> tuple[np.ndarray, np.ndarray, dict, dict | None, np.ndarray]:
        """Positions (N, n) from the closed forms, each block's σ picked at the first instant from
        ``target`` (the Newton solution, or the guess) and kept along the paths except where the two
        assemblies meet (a change point, reported in ``notes``); then cross-checked by the residual.
        ``known``: the inputs' cos and sin (see _compile), shared; also returned: those of the positions
        too, where every position is found and none was corrected (else None), and the instants whose
        position is not determined (a quadratic with every coefficient 0).

        A sweep of one input whose σ follows the motion is solved again on a denser sweep (``refine``
        rounds) where a step moves some unknown by more than ``MAX_CHANGE``, so no change point hides
        between coarse steps; ``outer``: the sweep as given, whose instants the notes name.  ``stop``: the
        level of block ``stop`` alone, with every σ given by ``chosen`` (see :meth:`_follow`)."""
        known = {} if known is None else known
        memo = {}  # the cos and sin of the unknowns computed here, with their arguments' bits (see _compile)
        N, n = len(u), len(self.unknowns)
        q, sigmas, undetermined = np.full((N, n), np.nan), {}, np.zeros(N, bool)
        structure = self._structure
        outer = u if outer is None else outer
        said, notes = notes, []  # the notes of this sweep, said unless a denser one replaces it
        following = False  # some block's σ follows the motion (a change point may swap it)
        for index, (form, (coefficients, second, linear, orientation)) in enumerate(zip(
                self._forms, self._closed_fns, strict=True)):
            first = self.unknowns.index(form.unknowns[0])
            column = None if form.second is None else self.unknowns.index(form.unknowns[1])
            kernel = self._kernels.get(form.unknowns[0].name)
            level_at = self._level_at(index, sigmas, tol, max_iter)
            if kernel is not None:
                sigmas[form.unknowns[0].name], level, _ = self._kernel_block(
                    kernel, form, q, u, paths, target, chosen, notes, level_at if stop is None else None,
                    outer)
                if stop == index:
                    return level
                following |= (chosen or {}).get(form.unknowns[0].name) is None
                undetermined |= np.isnan(q[:, first]) & (level >= -LEVEL)
                continue
            a, b, c = coefficients(self._values, q, u, known=known, memo=memo)
            if linear:
                q[:, first] = -c / b
            else:
                plus, minus, level = self._roots(a, b, c, form.kind)
                with np.errstate(invalid="ignore"):  # where an earlier block found nothing: no level
                    given = np.isfinite(a + b + c)
                    if not given.all():
                        level = np.where(given, level, np.nan)
                if stop == index:
                    return level
                undetermined |= np.isnan(plus) & (level >= -LEVEL)  # 0·v² + 0·v + 0: every v solves it
                name = form.unknowns[0].name
                wanted = (chosen or {}).get(name)
                # σ = −sign(det J_b) at the root the block is expected on (the other root's is the opposite)
                k = self._apart(plus, minus, paths)
                trial = self._trial(plus, minus, k, target, first, wanted, form, second, orientation, q, u)
                at_trial, det = self._at_root(form, second, orientation, q, u, plus if trial > 0 else minus,
                                              known, memo)
                side = np.sign(det)
                if trial > 0:
                    side = -side
                side[side == 0] = 1.0  # σ of the root +√Δ
                if wanted is None:  # σ where the roots first differ: the nearer root's (+1 without a target)
                    picked = 1 if target is None or k is None else int(trial * side[k])
                root = (picked if wanted is None else wanted) * side  # +1: the root +√Δ
                if wanted is None:  # σ named by assembly= holds at every instant; else it follows the motion
                    following = True
                    self._follow(root, level, paths, u, first, notes, level_at, outer)
                sigmas[name] = (root * side).astype(int)
                if (root == trial).all():  # on the expected root at every instant: its values are the block's
                    q[:, first] = at_trial[:, first]
                    if form.second is not None:
                        q[:, column] = at_trial[:, column]
                    continue
                q[:, first] = np.where(root > 0, plus, minus)
            if form.second is not None:
                q[:, column] = self._second(form, second, q, u, known, memo)
        if following and refine and u.shape[1] == 1 and N > 1:
            denser = self._denser(u, q)
            if denser is not None:  # coarse steps: the motion followed on a denser sweep, read at u
                dense = self._closed(denser, self._paths(denser), target, tol, max_iter, said, chosen, {},
                                     refine=refine - 1, outer=outer)
                q, iterations, sigmas, _, undetermined = dense
                return (q[:N], iterations[:N], {k: v[:N] for k, v in sigmas.items()}, None,
                        undetermined[:N])
        said.extend(notes)
        self._continuous(q, paths, target, u.shape[1] > 1)
        iterations = np.zeros(N, int)
        if len(self._kernels) == len(structure["forms"]):  # every block a registered kernel: no cross-check
            return q, iterations, sigmas, None, undetermined
        rows = self._scales[0]
        finite = _finite_rows(q)
        everywhere = bool(finite.all())
        at_q = dict(known)
        at = q if everywhere else np.where(finite[:, None], q, 0.0)
        F = self._F(at, u, at_q, same_point=True, memo=memo)  # (N, n): a view of one row per equation
        residual = None  # the largest |F_i| / rows_i per instant, equation by equation
        for i in range(n):
            size = np.abs(F[:, i])
            size /= rows[i]
            residual = size if residual is None else np.maximum(residual, size, out=residual)
        doubt = np.flatnonzero(finite & ~(residual <= RESIDUAL))
        for k in doubt:  # the cross-check: Newton from the closed form, kept only on the same assembly
            polished, fixed, count = self._correct(q[k], u[k], tol, max_iter)
            iterations[k] = count
            q[k] = polished if fixed and self._distance(polished, q[k]) <= MAX_CHANGE else np.nan
        return q, iterations, sigmas, at_q if everywhere and not len(doubt) else None, undetermined

    def _kernel_block(self, kernel, form, q, u, paths, target, chosen, notes, level_at=None, outer=None,
                      trig_wanted: bool = False) -> np.ndarray:
        """The block of ``form`` solved by its registered ``kernel`` into ``q``: σ from ``chosen``, else the
        assembly nearer ``target``, else +1, swapped at a change point as for a derived closed form (the
        other assembly computed only where the two come near); returns σ, the level per instant and the cos
        and sin the kernel gave for the values kept (with ``trig_wanted``; else, or where another σ was solved
        after, empty)."""
        columns = [self.unknowns.index(s) for s in form.unknowns]
        first, name = columns[0], form.unknowns[0].name
        known = {s.name: u[:, j] for j, s in enumerate(self.inputs)} | {
            s.name: q[:, j] for j, s in enumerate(self.unknowns) if s not in form.unknowns}
        parameters = {s.name: value for s, value in self.parameters.items()}

        def solved(sigma, where=None):
            """The block's values (one array (N',) per unknown) and level (N',) for σ, at the instants
            ``where`` (all: None), _BLOCK instants per call (the kernel's temporaries stay in the cache)."""
            at = {k: v if where is None else v[where] for k, v in known.items()}
            if np.ndim(sigma):  # σ per instant
                at["σ"] = sigma if where is None else sigma[where]
            size = len(u) if where is None else int(np.count_nonzero(where))
            trig.clear()
            parts = [slice(start, start + _BLOCK) for start in range(0, size, _BLOCK)]
            block = level = None  # one part: the kernel's own arrays; several: filled part by part
            if len(parts) > 1:
                block, level = [np.empty(size) for _ in columns], np.empty(size)
            for part in parts:
                given = {k: v[part] for k, v in at.items()}
                values, levels = kernel(parameters, given, given.pop("σ", sigma))
                count = min(part.stop, size) - part.start
                try:
                    these = [_instants(values[s.name], count) for s in form.unknowns]
                    this_level = _instants(levels, count)
                    for key in wanted_trig & values.keys():
                        if count == size:  # one part: the kernel's own arrays
                            trig[key] = _instants(values[key], count)
                        else:
                            trig.setdefault(key, np.empty(size))[part] = values[key]
                except (KeyError, TypeError, ValueError) as error:
                    raise InvalidArgumentError(f"the kernel of {name} must return the values of "
                                               f"{[s.name for s in form.unknowns]} by name and the level, "
                                               f"each of {count} instants; got {error!r}") from None
                if block is None:
                    block, level = these, this_level
                else:
                    for column, value in zip(block, these, strict=True):
                        column[part] = value
                    level[part] = this_level
            if block is None:  # no instants
                block, level = [np.empty(0) for _ in columns], np.empty(0)
            return block, level

        wanted_trig = {(s.name, func) for s in (*form.unknowns, *self.inputs) for func in ("cos", "sin")
                       } if trig_wanted else set()
        trig = {}  # the cos and sin the kernel gives, of the last values solved
        named = (chosen or {}).get(name)
        wanted = 1 if named is None else named
        block, level = solved(wanted)
        given = dict(trig)
        if named is None and target is not None:
            other, _ = solved(-1)
            wanted = self._pick(block[0], other[0], paths, target, first, np.ones(len(u)))
            if wanted == -1:
                block, other = other, block
        root = np.ones(len(u))
        if named is None and u.shape[1] == 1 and len(u) > 1 and level_at is not None:
            self._follow(root, level, paths, u, first, notes, level_at, outer, block[0])
        swapped = bool((root < 0).any())
        if swapped:
            other, _ = solved(-wanted)
            block = [np.where(root > 0, mine, theirs) for mine, theirs in zip(block, other, strict=True)]
        for column, values in zip(columns, block, strict=True):
            q[:, column] = values
        if swapped or named is None and target is not None and wanted == -1:
            given = {}  # another σ solved after: its cos and sin not kept
        return (wanted * root).astype(int), level, given

    def _second(self, form, second, q, u, known=None, memo=None) -> np.ndarray:
        """The block's second unknown from its first (already in ``q``)."""
        values = second(self._values, q, u, known=known, memo=memo)
        return np.arctan2(values[1], values[0]) if form.second[0] == "angle" else values[0]

    def _apart(self, plus, minus, paths) -> int | None:
        """The first instant (along the paths) where the two roots are both found and differ; None if none
        (the first few instants looked at one by one, as most sweeps start there; then all at once)."""
        def apart(k):
            return ((np.isfinite(plus[k]) & np.isfinite(minus[k]))
                    & (self._distance(plus[k][..., None], minus[k][..., None], [0]) > 1e-7))

        order = np.concatenate(paths) if len(paths) > 1 else np.asarray(paths[0])
        for k in order[:4]:
            if apart(k):
                return int(k)
        found = np.flatnonzero(apart(order[4:]))
        return int(order[4 + found[0]]) if len(found) else None

    def _nearer(self, plus, minus, k, target, first) -> int:
        """The root nearer ``target`` at the instant ``k``: +1 the root +√Δ, −1 the other."""
        both = np.array([plus[k], minus[k]])
        size = self._scales[1][first]
        gaps = np.abs(both - target[first])
        if self.unknowns[first] in self._structure["angles"]:
            gaps = np.abs(_unwrap_to(both - target[first], 0.0))
        return 1 if gaps[0] * size <= gaps[1] * size else -1

    def _pick(self, plus, minus, paths, target, first, side) -> int:
        """σ at the first instant (along the paths) where the two roots differ: the one nearer ``target``
        (``side``: the σ of the root +√Δ per instant)."""
        k = None if target is None else self._apart(plus, minus, paths)
        return 1 if k is None else int(self._nearer(plus, minus, k, target, first) * side[k])

    def _trial(self, plus, minus, k, target, first, wanted, form, second, orientation, q, u) -> int:
        """The root (+1: +√Δ, −1 the other) the block is expected on at every instant, where σ is decided
        once for the whole sweep: at ``k``, the first instant where the two differ (None: none does), the
        root nearer ``target``, or the one with the ``wanted`` σ (det J_b at that one instant).  Only a
        saving: the block's σ is decided by det J_b at this root, and the values computed for it are kept
        where it is the root chosen."""
        if k is None:
            return 1
        if wanted is None and target is not None:
            return self._nearer(plus, minus, k, target, first)
        _, det = self._at_root(form, second, orientation, q[k:k + 1], u[k:k + 1], plus[k:k + 1])
        sigma = 1 if wanted is None else int(np.ravel(wanted)[k if np.size(wanted) > 1 else 0])
        return sigma if det[0] <= 0 else -sigma

    def _at_root(self, form, second, orientation, q, u, values, known=None, memo=None
                 ) -> tuple[np.ndarray, np.ndarray]:
        """``q`` with the block's first unknown set to ``values`` (a root) and its second solved from it, and
        det J_b there (unknowns not found taken as 0 where det J_b reads them; the others not read at all)."""
        at = q.copy()
        at[:, self.unknowns.index(form.unknowns[0])] = values
        if form.second is not None:
            at[:, self.unknowns.index(form.unknowns[1])] = self._second(form, second, at, u, known, memo)
        read = at[:, orientation.reads[0]]
        finite = at if np.isfinite(read).all() else np.where(np.isfinite(at), at, 0.0)
        return at, orientation(self._values, finite, u, memo=memo)[0]

    def _level_at(self, index: int, sigmas: Mapping, tol, max_iter) -> Callable:
        """(points (K, m), left (K,)) → the level of block ``index`` at the inputs ``points``, the blocks
        before it on the assemblies they have at the instants ``left``."""
        earlier = dict(sigmas)
        name = self._forms[index].unknowns[0].name

        def level_at(points, left):
            chosen = {key: np.asarray(value)[left] for key, value in earlier.items()} | {name: 1}
            with np.errstate(all="ignore"):
                return self._closed(points, [np.arange(len(points))], None, tol, max_iter, [], chosen, {},
                                    refine=0, stop=index)

        return level_at

    def _denser(self, u: np.ndarray, q: np.ndarray) -> np.ndarray | None:
        """The sweep of one input ``u`` with instants added between neighbours (in the input's order) where a
        step moves some unknown by more than ``MAX_CHANGE`` (each such step cut in up to 16); None where no
        step does."""
        values = u[:, 0]
        with np.errstate(all="ignore"):
            if (np.diff(values) >= 0).all():  # in increasing order already (most sweeps): no sort
                gap = self._distance(q[1:], q[:-1])
                coarse = np.flatnonzero(gap > MAX_CHANGE)
                before, after = coarse, coarse + 1
            else:
                order = np.argsort(values, kind="stable")
                gap = self._distance(q[order[1:]], q[order[:-1]])
                coarse = np.flatnonzero(gap > MAX_CHANGE)
                before, after = order[coarse], order[coarse + 1]
        if not len(coarse):
            return None
        gap = gap[coarse]
        parts = np.minimum(np.ceil(2 * gap / MAX_CHANGE), 16).astype(int)
        added = [values[a] + (values[b] - values[a]) * np.arange(1, p) / p
                 for a, b, p in zip(before, after, parts, strict=True)]
        return np.concatenate([values, *added])[:, None]

    @staticmethod
    def _lowest(level_at, start: np.ndarray, end: np.ndarray, left: np.ndarray, rounds: int = 12
                ) -> tuple[np.ndarray, np.ndarray]:
        """Where the level is lowest between the inputs ``start`` and ``end`` (K, m), and that level: the
        interval sampled at 17 points and narrowed to the lowest one's neighbours, ``rounds`` times (each
        round 8 times narrower)."""
        K, m = start.shape
        samples = np.linspace(0.0, 1.0, 17)
        low, high = start.astype(float), end.astype(float)
        rows = np.arange(K)
        for _ in range(rounds):
            points = low[:, None, :] + samples[None, :, None] * (high - low)[:, None, :]
            level = level_at(points.reshape(-1, m), np.repeat(left, len(samples))).reshape(K, -1)
            best = np.argmin(np.where(np.isnan(level), np.inf, level), axis=1)
            found, value = points[rows, best], level[rows, best]
            low = points[rows, np.maximum(best - 1, 0)]
            high = points[rows, np.minimum(best + 1, len(samples) - 1)]
        return found, value

    def _follow(self, root, level, paths, u, first, notes, level_at, outer, values=None) -> None:
        """Swap the root (``root``: +1 the root +√Δ, −1 the other, per instant) where the block's two
        assemblies meet between neighbouring instants (a change point): there the other root continues the
        motion smoothly, and σ changes.  Where the level comes near 0 (a local lowest below 0.1) the lowest
        level between the neighbours is located (:meth:`_lowest`, the earlier blocks as at the first of
        them); the assemblies meet only where it reaches ``CHANGE_LEVEL`` — above it they come near and
        part again (a near miss), and σ is kept.  The note names the change point where it is, and the
        instants of ``outer`` (the sweep as given) around it."""
        if u.shape[1] > 1 or not (level < 0.1).any():  # several inputs: no order of neighbours to follow,
            return  # each instant keeps its σ; nowhere near each other: the assemblies do not meet
        name = self.unknowns[first].name
        solved = (level >= -LEVEL) if values is None else (level >= -LEVEL) & np.isfinite(values)
        for path in paths:
            if len(path) < 2:
                continue
            lv = np.where(solved[path], level[path], np.nan)
            lowest = np.zeros(len(path), bool)  # a local lowest of the level along the path
            lowest[1:-1] = (lv[1:-1] <= lv[:-2]) & (lv[1:-1] <= lv[2:])
            lowest[0], lowest[-1] = lv[0] <= lv[1], lv[-1] <= lv[-2]
            near = (np.minimum(lv[:-1], lv[1:]) < 0.1) & (lowest[:-1] | lowest[1:])
            steps = np.flatnonzero(near)
            if not len(steps):
                continue
            start, end = u[path[steps]], u[path[steps + 1]]
            where, value = self._lowest(level_at, start, end, path[steps])
            width = np.abs(end - start).max(axis=1)
            at_start = np.abs(where - start).max(axis=1) <= 1e-8 * width
            at_end = np.abs(where - end).max(axis=1) <= 1e-8 * width
            met = value <= CHANGE_LEVEL
            # on an instant, the assemblies meet only if the motion goes on through it: the steps on both
            # sides of it find it, and it counts once (at the first); else the motion starts or stops there
            # (the path's ends, a limit the sweep ends at or turns back from)
            both = np.zeros(len(steps), bool)
            both[:-1] = met[:-1] & met[1:] & at_end[:-1] & at_start[1:] & (steps[1:] == steps[:-1] + 1)
            met &= ~(at_start | at_end) | both
            for k in np.flatnonzero(met):
                root[path[steps[k] + 1:]] *= -1
                notes.append(f"the two assemblies of {name} meet (a change point) at "
                             f"{self._around(where[k], outer)}: the motion continues on the smooth one "
                             "(σ swapped there)")

    def _around(self, point: np.ndarray, outer: np.ndarray) -> str:
        """An input ``point`` (one input) in words, with the instants of the sweep ``outer`` around it."""
        symbol, value = self.inputs[0], float(point[0])
        given = outer[:, 0]
        close = np.abs(given - value) <= 1e-9 * max(1.0, abs(value))
        unit = 1.0 if self._units is None else float(self._units.u[0])  # a twin's: said in the declaration's
        if unit != 1.0:
            value, given = value * unit, given * unit
        if close.any():
            return f"{symbol.name}={given[np.argmax(close)]!r}, an instant of the sweep"
        below, above = given[given < value], given[given > value]
        text = f"{symbol.name}≈{value:.6f}" if unit == 1.0 else f"{symbol.name}≈{value:.6g}"
        if len(below) and len(above):
            text += (f", between the instants {symbol.name}={float(below.max())!r} and "
                     f"{symbol.name}={float(above.min())!r}")
        return text

    def _continuous(self, q, paths, target, several: bool = False) -> None:
        """Angles unwrapped along each path, the first instant's within π of ``target`` (in [−π, π]
        without one); with ``several`` inputs (no order of neighbours) every instant's like the first's."""
        angles = [j for j, s in enumerate(self.unknowns) if s in self._structure["angles"]]
        if several and angles:
            q[:, angles] = _unwrap_to(q[:, angles], 0.0 if target is None else target[angles])
            return
        columns = [j for j in angles if np.isfinite(q[0, j])]
        if len(columns) < len(angles):  # no first instant to follow from: each in [−π, π]
            lost = [j for j in angles if j not in columns]
            q[:, lost] = _unwrap_to(q[:, lost], 0.0)
        if not columns:
            return
        q[0, columns] = _unwrap_to(q[0, columns], 0.0 if target is None else target[columns])
        for path in paths:
            ordered = len(path) > 1 and path[0] == 0 and path[-1] == len(path) - 1 \
                and bool((np.diff(path) == 1).all())
            rows = slice(0, len(path)) if ordered else path
            values = q[rows][:, columns]
            finite = _finite_rows(values)
            if not finite[0] or finite.sum() < 2:
                continue
            if not finite.all():
                rows, values = path[finite], values[finite]
            # each step within π: whole turns taken off, counted along the path, unknown by unknown (a
            # column with every step within π has no turn to take off)
            for k in range(len(columns)):
                steps = np.diff(values[:, k])
                if not (np.abs(steps) > np.pi).any():
                    continue
                turns = np.round(steps / (2 * np.pi))
                np.cumsum(turns, out=turns)
                if not turns.any():
                    continue
                kept = values[1:, k] - 2 * np.pi * turns
                if isinstance(rows, slice):
                    q[1:len(path), columns[k]] = kept
                else:
                    q[rows[1:], columns[k]] = kept
