"""The course's two Newton routes: consecutive (position, velocity, acceleration in turn) and simultaneous
(the 3n system at once).

One room of :class:`~course_lib.mechanism.Mechanism`, which is all of them together.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np

from ..errors import (
    ConvergenceError,
    InvalidGeometryError,
    SingularJacobianError,
    require_choice,
)
from ..newton import (
    BatchNewtonResult,
    LinearStack,
    NewtonResult,
    newton,
    newton_batch,
    singular_jacobian_text,
)

if TYPE_CHECKING:
    from . import Mechanism

LINEAR_STAGES = ("newton", "direct")


class Routes:
    """The course's consecutive and simultaneous Newton routes."""

    def _run(self, stage, u, terms, start, tol, max_iter, direct=False, jacobian=None):
        """One Newton stage from ``start`` (k,) or (N, k); ``terms(x)`` gives (F, J), or F alone for a
        linear stage of constant ``jacobian`` (``direct``: one linear solve).  Failures raise, named."""
        batch = start.ndim == 2
        if direct:
            F0 = terms(start)
            stack = jacobian if batch else LinearStack(jacobian[None])
            stuck = stack.ill_conditioned
            if batch and stuck.any():
                stack = LinearStack(np.where(stuck[:, None, None], np.eye(start.shape[-1]), stack.matrices))
            x = start + stack.solve(-(F0 if batch else F0[None])).reshape(start.shape)
            residual = np.linalg.norm(terms(x), axis=-1)
            if batch:
                result = BatchNewtonResult(x, residual <= tol, np.ones(len(x), int), stuck,
                                           np.linalg.norm(x - start, axis=-1), residual, "one linear solve")
            else:
                step = x - start
                result = NewtonResult(x, bool(residual <= tol), 1, np.array([start, x]),
                                      np.array([np.linalg.norm(step)]), np.abs(step)[None, :],
                                      np.array([np.linalg.norm(F0), residual]), "one linear solve",
                                      bool(stuck[0]))
        elif jacobian is not None and batch:
            result = newton_batch(terms, start, jac=jacobian, tol=tol, max_iter=max_iter)
        elif jacobian is not None:
            result = newton(terms, start, jac=lambda v: jacobian, tol=tol, max_iter=max_iter,
                            on_failure="report")
        elif batch:
            result = newton_batch(terms, start, jac=True, tol=tol, max_iter=max_iter)
        else:
            result = newton(lambda v: terms(v)[0], start, jac=lambda v: terms(v)[1], tol=tol,
                            max_iter=max_iter, on_failure="report")
        if np.all(result.converged) and not np.any(result.ill_conditioned):
            return result
        failed = np.flatnonzero(~np.atleast_1d(result.converged) | np.atleast_1d(result.ill_conditioned))
        first = failed[0]
        where = self._where(u, first)
        if batch:
            what = ("the Jacobian became ill-conditioned" if result.ill_conditioned[first]
                    else "Newton did not converge")
            message = (f"{stage} stage at {where}: {what} ({failed.size} of {len(start)} points, first at "
                       f"index {first})")
        else:
            message = f"{stage} stage at {where}: " + (
                f"the Jacobian is {singular_jacobian_text(start.size)}" if direct else result.message)
        if np.atleast_1d(result.ill_conditioned)[first]:
            raise SingularJacobianError(message, x=result.x[first].tolist() if batch else result.x.tolist())
        raise ConvergenceError(message, result=result)

    def consecutive(self, u, u_rate, u_acceleration, seed, *, tol: float = 1e-6, max_iter: int = 50,
                    linear_stages: str = "newton", position: Mechanism | None = None) -> dict:
        """The course's consecutive Newton: position, then velocity, then acceleration, each stage run
        from its third of ``seed`` (q, q̇, q̈: 3n values); returns {stage: result}.

        ``u``, ``u_rate``, ``u_acceleration``: (m,) for one instant (``NewtonResult`` s with history) or
        (N, m) (:func:`newton_batch`).  ``linear_stages="direct"`` solves the linear rate stages in one
        step; ``position``: an equivalent declaration (e.g. a constraint substituted) for stage one.

        >>> th, x = sp.symbols("theta x")
        >>> stages = Mechanism([x**2 - th], [x], [th]).consecutive([4.0], [1.0], [0.0], [1.0, 0.0, 0.0])
        >>> [(stage, round(float(r.x[0]), 6), r.iterations) for stage, r in stages.items()]
        [('position', 2.0, 5), ('velocity', 0.25, 2), ('acceleration', -0.03125, 2)]
        """
        require_choice("linear_stages", linear_stages, LINEAR_STAGES)
        u, u_rate, u_acc, seed = self._route_arguments(u, u_rate, u_acceleration, seed, position)
        n, batch = len(self.unknowns), u.ndim == 2
        start = np.broadcast_to(seed, (len(u), seed.size)) if batch else seed
        form, known, seen = position or self, {}, {}
        position = self._run("position", u, lambda v: form._newton_terms(v, u, known, seen), start[..., :n],
                             tol, max_iter)
        # newton_batch evaluates F last at the x it returns: the cos and sin seen there are those of q
        q, at_q = position.x, {**known, **seen} if batch else dict(known)
        J, F_u = self._rate_terms(q, u, at_q, same_point=True)
        jacobian = LinearStack(J) if batch else J  # both linear stages: one J, prepared once

        def linear(stage, constant, guess):
            def residual(v):
                return np.einsum("...ij,...j->...i", J, v) + constant

            return self._run(stage, u, residual, guess, tol, max_iter, direct=linear_stages == "direct",
                             jacobian=jacobian)

        velocity = linear("velocity", np.einsum("...ij,...j->...i", F_u, u_rate), start[..., n:2 * n])
        rest = self._rhs(q, velocity.x, u, u_rate, u_acc, at_q)
        acceleration = linear("acceleration", -rest, start[..., 2 * n:])
        return {"position": position, "velocity": velocity, "acceleration": acceleration}

    def simultaneous(self, u, u_rate, u_acceleration, seed, *, tol: float = 1e-6, max_iter: int = 50,
                     position: Mechanism | None = None):
        """The course's simultaneous Newton on the 3n system (:meth:`system`); arguments as in consecutive.

        >>> th, x = sp.symbols("theta x")
        >>> result = Mechanism([x**2 - th], [x], [th]).simultaneous([4.0], [1.0], [0.0], [1.0, 0.0, 0.0])
        >>> np.round(result.x, 6).tolist(), result.iterations
        ([2.0, 0.25, -0.03125], 5)
        """
        u, u_rate, u_acc, seed = self._route_arguments(u, u_rate, u_acceleration, seed, position)
        start = np.broadcast_to(seed, (len(u), seed.size)) if u.ndim == 2 else seed
        return self._run("simultaneous", u, lambda x: self.system(x, u, u_rate, u_acc, position), start, tol,
                         max_iter)

    def _route_arguments(self, u, u_rate, u_acceleration, seed, position):
        """The checked arguments of the course's two routes: u, u̇, ü (m,) or (N, m) alike, seed (3n,)."""
        u, u_rate, u_acc, seed = self._checked(u=u, u_rate=u_rate, u_acceleration=u_acceleration, seed=seed)
        self._check_position(position)
        if u.ndim > 2 or seed.ndim != 1 or not (u.shape == u_rate.shape == u_acc.shape):
            raise InvalidGeometryError(f"u, u_rate and u_acceleration must share one shape, (m,) or (N, m), "
                                       f"and seed must be one vector of 3n values; got shapes {u.shape}, "
                                       f"{u_rate.shape}, {u_acc.shape} and {seed.shape}")
        return u, u_rate, u_acc, seed
