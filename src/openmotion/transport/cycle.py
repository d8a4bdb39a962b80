"""The cycle of a CA group: proposals, the gap filter, held movers, command events.

``GroupCycle`` is the half of ``CaGroup`` that runs every cycle, right after the profiles
are evaluated (Runtime phase 2); group.py holds the administration and the commands.
docs/collision-avoidance.md describes the algorithm and its safety argument.
"""

from __future__ import annotations

import math
from typing import TYPE_CHECKING

import numpy as np

from openmotion.axis.commands import CommandStatus
from openmotion.core.errors import CommandRejected
from openmotion.core.special_values import MC_DEFAULT
from openmotion.rail.braking import brake_envelope, brake_state
from openmotion.rail.gap_control import Pairs, filter_steps
from openmotion.rail.gear import GearSync
from openmotion.rail.kernels import fast_candidates
from openmotion.rail.tolerances import TOLERANCE
from openmotion.trajectory.plan import Limits, plan_position
from openmotion.trajectory.segments import KinematicState
from openmotion.transport.cycle_kernel import (
    group_step,
    no_command,
    pair_arrays,
    resume,
    rooms,
)
from openmotion.transport.enums import GapControlDirection, GapControlMode, GroupState
from openmotion.transport.faults import FAULT_STATES
from openmotion.transport.movers import (
    FOLLOW,
    GEAR,
    HALT,
    HELD,
    IDLE,
    MOVING_STATES,
    STANDBY,
    CaJob,
    Mover,
)
from openmotion.transport.tolerances import (
    FIT_SLACK,
    LIMIT_TOLERANCE,
    REST_SHARE,
    STANDBY_DISTANCE,
)

if TYPE_CHECKING:
    pass


class GroupCycle:
    """The per-cycle methods of ``CaGroup`` (a mixin: the state lives in the group)."""

    #: run the cycle as one compiled call where it can (cycle_kernel.py); False: always the
    #: numpy formulation, the reference the tests compare it with
    compiled_cycle = True


    def pairs_changed(self) -> None:
        """The order, modes or gap paths of the movers changed: the pairs and the room
        between them are found again in the next cycle."""
        self._pairs_dirty = True
        self._room_of = None

    def _pairs(self) -> Pairs:
        if self._pairs_dirty:
            succ, pred, offset, gap, fast = pair_arrays(  # one compiled pass (D-281)
                self.pred, self.gmode, int(GapControlMode.NONE), int(GapControlMode.FAST),
                self.fast_grace, self.offset, self.gap)
            both = self.parameters.gap_control_direction is GapControlDirection.BOTH
            y, path = self.tracks.gap_paths(succ)
            self._pair_cache = Pairs(succ, pred, offset, gap, fast, both, y, path)
            self._pairs_dirty = False
        return self._pair_cache

    def advance(self, now: float) -> None:
        """Phase 2, after the profiles: gap control and the movers' command events."""
        if self.state in FAULT_STATES:  # brakes run only there (faults.py)
            self._follow_brakes(now)  # first, so that a reset sees where they are
        if self._reset is not None:
            self._end_reset()
        if not self.movers:
            return
        self._watch_members()
        if self.state not in MOVING_STATES:
            if self.state is not GroupState.DISABLED:  # the brakes' states, for the next fault
                k, rows = self.kernel, self.rows
                self.p, self.v, self.a = k.set_p[rows], k.set_v[rows], k.set_a[rows]
                self._env = None
            return
        k, rows, dt = self.kernel, self.rows, self.runtime.cycle_time
        pairs = self._pairs()
        if self.compiled_cycle and pairs.y is None and self._advance_compiled(now, pairs):
            return
        nxt = [k.set_p[rows].copy(), k.set_v[rows].copy(), k.set_a[rows].copy(),
               k.set_j[rows].copy()]
        n = rows.size
        known = (np.zeros(n, dtype=bool), np.empty(n), np.empty(n))  # proposal envelopes
        self._leave_stale_queues()
        held = np.flatnonzero(self.mode == HELD)
        if held.size:
            held = self._waiting(held, nxt, known)
        if held.size:
            for field_, value in zip(nxt, self._track(held, dt, known), strict=True):
                field_[held] = value
        idle = self.mode == IDLE
        if idle.any():  # no command: the mover rests where it is
            nxt[0][idle], nxt[1][idle], nxt[2][idle], nxt[3][idle] = self.p[idle], 0.0, 0.0, 0.0
            known[0][idle], known[1][idle], known[2][idle] = True, self.p[idle], self.p[idle]
        geared = np.flatnonzero(self.mode == GEAR)
        if geared.size:
            self._gear_steps(geared, now, nxt)
        cur = (self.p, self.v, self.a)
        braking, lo, hi = filter_steps(cur, self._envelope(), nxt, dt, self.bdec,
                                       self.bjerk, self._pairs(), known)
        k.set_p[rows], k.set_v[rows], k.set_a[rows], k.set_j[rows] = nxt
        self.p, self.v, self.a = nxt[0], nxt[1], nxt[2]
        self._env = (lo, hi)
        if self.fast_grace.any():
            self._end_fast_grace(lo, hi)
        self.mode[braking & (self.mode == FOLLOW)] = HELD
        for slot in np.flatnonzero(braking & (self.mode == GEAR)).tolist():
            sync = self.movers[slot].job.extra  # type: ignore[union-attr]
            sync.held(now, (float(self.p[slot]), float(self.v[slot]), float(self.a[slot])),
                      self._master(sync))
        self._events(now)

    def _advance_compiled(self, now: float, pairs: Pairs) -> bool:
        """``advance`` in one compiled call (cycle_kernel.py, D-281): the same steps, the
        same numbers; Python only for the movers whose job ends or replans. The states and
        envelopes are written in place: the envelope of two cycles ago is this cycle's
        buffer (no allocation per cycle). False: a coupled mover, nothing done."""
        k, rows = self.kernel, self.rows
        n = rows.size
        lo_cur, hi_cur = env = self._envelope()
        spare = self._spare_env
        if spare is None or spare[0].size != n or spare[0] is lo_cur:
            spare = (np.empty(n), np.empty(n))
            self._slot_buf, self._goal_buf = np.empty(2 * n, dtype=np.int64), np.empty((n, 5))
        lo, hi = spare
        slots, goals = self._slot_buf, self._goal_buf
        grace_changed, ended, nf, nr, idle = group_step(
            self.runtime.cycle_time, now, rows, k.set_p, k.set_v, k.set_a, k.set_j,
            k.segments.end, self.p, self.v, self.a, self.mode, self.goal, self.target,
            self.lim, self.halting, self.bdec, self.bjerk, self.pred, self.succ, lo_cur,
            hi_cur, pairs.succ, pairs.pred, pairs.offset, pairs.gap, pairs.fast, pairs.both,
            self.fast_grace, lo, hi, slots, goals)
        if grace_changed < 0:
            return False
        self._env, self._spare_env = (lo, hi), env
        if grace_changed:
            self.pairs_changed()
        if ended:
            self._end_profiles(slots[:ended].copy())
            pairs = self._pairs()
            room_hi, room_lo = rooms(lo, hi, pairs.succ, pairs.pred, pairs.offset, pairs.gap,
                                     pairs.both)
            finish, replan, there, limits = resume(
                self.p, self.v, self.a, self.mode, self.target, self.lim, self.halting,
                self.bdec, self.bjerk, self.pred, self.succ, lo, hi, room_hi, room_lo)
            self._apply_resume(finish.tolist(), replan.tolist(), there.tolist(),
                               limits.tolist())
        elif nf or nr:
            self._apply_resume(slots[:nf].tolist(), slots[nf:nf + nr].tolist(),
                               goals[:nr, 0].tolist(), goals[:nr, 1:].tolist())
        self._after_resume(now, idle if not (ended or nf or nr) else None)
        return True

    def _apply_resume(self, finish: list[int], replan: list[int], goals: list[float],
                      limits: list[list[float]]) -> None:
        """What ``resume`` decided: jobs that end, profiles to plan (as ``_resume``)."""
        for slot in finish:
            self._finish_job(self.movers[slot])
        for slot, goal, lim in zip(replan, goals, limits, strict=True):
            self._replan(self.movers[slot], goal, None if math.isnan(lim[0]) else Limits(*lim))

    def _leave_stale_queues(self) -> None:
        """A mover on its way to a queue place tracks again once the neighbour in its way has
        moved on: that place is no longer where it must wait, and its profile would bring it
        to rest short of the new one, to start again a cycle later (D-210)."""
        queued = np.flatnonzero((self.mode == FOLLOW) & ~self.halting
                                & np.isfinite(self.goal) & (self.goal != self.target))
        if not queued.size:
            return
        room_hi, room_lo = self._room(queued)
        goal = self.goal[queued]
        grown = np.where(self.target[queued] >= goal, room_hi > goal + TOLERANCE,
                         room_lo < goal - TOLERANCE)
        self.mode[queued[grown]] = HELD

    def _end_fast_grace(self, lo: np.ndarray, hi: np.ndarray) -> None:
        """Pairs switched from FAST to STANDARD become STANDARD once safe in that sense."""
        pairs = self._pairs()
        m = np.flatnonzero(self.fast_grace[pairs.succ])
        s, k = pairs.succ[m], pairs.pred[m]
        safe = hi[s] + pairs.gap[m] <= lo[k] + pairs.offset[m] + TOLERANCE
        tcp = pairs.on_tcp(m)
        if tcp.any():
            safe[tcp] = hi[s[tcp]] <= pairs.behind(m[tcp], lo[k[tcp]] + pairs.offset[m[tcp]]) \
                + TOLERANCE
        if safe.any():
            self.fast_grace[s[safe]] = False
            self.pairs_changed()
        self.fast_grace[self.pred < 0] = False  # no pair at all

    def _master(self, sync: GearSync) -> tuple[float, float, float, float]:
        k, row = self.kernel, sync.master_row
        return float(k.set_p[row]), float(k.set_v[row]), float(k.set_a[row]), float(k.set_j[row])

    def _gear_steps(self, slots: np.ndarray, now: float, nxt: list[np.ndarray]) -> None:
        """Proposals of coupled slaves (few: a loop); a failed sync ends in error and brakes."""
        dt = self.runtime.cycle_time
        for slot in slots.tolist():
            mover = self.movers[slot]
            job = mover.job
            assert job is not None
            sync: GearSync = job.extra
            state = (float(self.p[slot]), float(self.v[slot]), float(self.a[slot]))
            try:
                proposal = sync.step(now, state, self._master(sync), dt)
            except CommandRejected as rejected:
                sync.error = (rejected.error_id, rejected.message)
                proposal = None
            if sync.error is not None:
                job.command.end(CommandStatus.ERROR, now, *sync.error)
                mover.job = None
                self._issue_halt(mover, self._command("halt"), MC_DEFAULT, MC_DEFAULT,
                                 mover.gap, GapControlMode.GROUP_DEFAULT)
                proposal = None
            if proposal is None:  # waiting (or stopping): brake to rest with the job's limits
                lim = job.limits  # or on along gap control's harder brake (D-206)
                v, a = float(self.v[slot]), float(self.a[slot])
                slack = 1 + LIMIT_TOLERANCE
                hard = abs(a) > lim.deceleration * slack or (  # or it would turn round
                    v * a < 0.0 and a * a / (2.0 * lim.jerk) > abs(v) * slack)
                dec = self.bdec[slot] if hard else lim.deceleration
                jerk = self.bjerk[slot] if hard else lim.jerk
                step = brake_state(self.p[slot:slot + 1], self.v[slot:slot + 1],
                                   self.a[slot:slot + 1], np.array([dec]), np.array([jerk]),
                                   dt)
                proposal = tuple(float(x[0]) for x in step)
            for field_, value in zip(nxt, proposal, strict=True):
                field_[slot] = value

    def _waiting(self, held: np.ndarray, nxt: list[np.ndarray],
                 known: tuple[np.ndarray, np.ndarray, np.ndarray]) -> np.ndarray:
        """Held movers standing with no room at all towards their target stay as they are
        (a queue behind a mover that stands or waits itself), and so do standing movers that
        want to go back into the room a successor wants to go forward into (head on: the
        mover moving forwards takes it); returns the others."""
        still = (self.v[held] == 0.0) & (self.a[held] == 0.0) & ~self.halting[held]
        if not still.any():
            return held
        room_hi, room_lo = self._room(held)
        p = self.p[held]
        forward = self.target[held] >= p
        room = np.where(forward, room_hi - p, p - room_lo)
        stay = still & ((room <= TOLERANCE) | (~forward & self._head_on(held)))
        slots = held[stay]
        nxt[0][slots], nxt[1][slots], nxt[2][slots], nxt[3][slots] = self.p[slots], 0.0, 0.0, 0.0
        known[0][slots], known[1][slots], known[2][slots] = True, self.p[slots], self.p[slots]
        return held[~stay]

    def _head_on(self, slots: np.ndarray) -> np.ndarray:
        """The successor of each mover has a command that takes it forwards."""
        succ = self.succ[slots]
        waiting = succ >= 0
        waiting[waiting] = (self.mode[succ[waiting]] != IDLE) & \
            (self.target[succ[waiting]] > self.p[succ[waiting]] + TOLERANCE)
        return waiting

    def _envelope(self) -> tuple[np.ndarray, np.ndarray]:
        """Brake envelope of the current states (cached from the last cycle)."""
        if self._env is None:
            self._env = brake_envelope(self.p, self.v, self.a, self.bdec, self.bjerk)
        return self._env

    def _track(self, held: np.ndarray, dt: float,
               known: tuple[np.ndarray, np.ndarray, np.ndarray]) -> tuple[np.ndarray, ...]:
        """The next step of held movers: the most progressive constant-jerk step (jerk +J,
        0 or -J) that stays within the command's limits, does not pass the target and keeps
        clear of the neighbours as they are now; else a brake. Held movers never turn back.

        All three candidates of all held movers are evaluated in one vectorised pass (three
        passes over few movers cost more than one over three times as many)."""
        m = held.size
        p, v, a = self.p[held], self.v[held], self.a[held]
        vmax, acc, dec, jmax = self.lim.take(held, axis=1)
        bdec, bjerk = self.bdec[held], self.bjerk[held]
        target = self.target[held]
        sign = np.where(target >= p, 1.0, -1.0)
        room_hi, room_lo = self._room(held)
        lo_now, hi_now = self._envelope()
        room_hi = np.maximum(room_hi, hi_now[held])
        room_lo = np.minimum(room_lo, lo_now[held])
        out = [np.empty(m) for _ in range(4)]
        rows = np.flatnonzero(~self.halting[held])
        if rows.size:
            rows = self._candidates(rows, held, dt, (p, v, a, sign, target),
                                    (vmax, acc, dec, jmax, bdec, bjerk), (room_lo, room_hi),
                                    self._ahead(held, sign, dt), out, known)
        lost = np.zeros(m, dtype=bool)
        lost[rows] = True
        lost |= self.halting[held]
        if lost.any():  # no step fits: the command's own brake, or the mover's hardest one
            # where gap control braked it beyond what the command's brake can take back
            # without turning round
            u, b = sign[lost] * v[lost], sign[lost] * a[lost]
            hard = (b < -dec[lost]) | (u + b * np.abs(b) / (2.0 * jmax[lost]) < 0.0)
            step = brake_state(p[lost], v[lost], a[lost],
                               np.where(hard, bdec[lost], dec[lost]),
                               np.where(hard, bjerk[lost], jmax[lost]), dt)
            for o, value in zip(out, step, strict=True):
                o[lost] = value
        # float residue of the steps (|v| ~ 1e-17) is rest: snap it, so standstill is exact
        still = (np.abs(out[1]) <= REST_SHARE * vmax) & (np.abs(out[2]) <= REST_SHARE * acc)
        out[1][still], out[2][still], out[3][still] = 0.0, 0.0, 0.0
        known[0][held[still]] = False  # snapped: the filter computes their envelope
        return tuple(out)

    def _ahead(self, held: np.ndarray, sign: np.ndarray, dt: float) -> np.ndarray:
        """For each held mover moving forwards in a FAST pair: its predecessor's brake a
        cycle on (p, v, a, dec, jerk) and the gap, which the tracking step may keep braking
        together with it rather than within the STANDARD room (D-211); nan rows: none."""
        ahead = np.full((held.size, 6), np.nan)
        pairs = self._pairs()
        pair_of = np.full(len(self.movers), -1)
        pair_of[pairs.succ] = np.arange(pairs.succ.size)
        m = pair_of[held]
        use = (m >= 0) & (sign > 0.0)
        use[use] = pairs.fast[m[use]]
        if use.any():
            m = m[use]
            k = pairs.pred[m]
            p, v, a, _ = brake_state(self.p[k] + pairs.offset[m], self.v[k], self.a[k],
                                     self.bdec[k], self.bjerk[k], dt)
            ahead[use] = np.column_stack((p, v, a, self.bdec[k], self.bjerk[k], pairs.gap[m]))
        return ahead

    @staticmethod
    def _candidates(rows: np.ndarray, held: np.ndarray, dt: float,
                    state: tuple[np.ndarray, ...], limits: tuple[np.ndarray, ...],
                    room: tuple[np.ndarray, np.ndarray], ahead: np.ndarray,
                    out: list[np.ndarray],
                    known: tuple[np.ndarray, np.ndarray, np.ndarray]) -> np.ndarray:
        """Write the first fitting step (+J, 0, -J) of each of ``rows`` into ``out``; returns
        the rows that no step fits (one compiled loop, kernels.fast_candidates)."""
        m = held.size
        steps, env = np.empty((4, m)), np.empty((2, m))
        arrays = (np.ascontiguousarray(x, dtype=float) for x in (*state, *limits, *room))
        fitted = fast_candidates(rows, dt, *arrays, np.ascontiguousarray(ahead[rows]), steps,
                                 env)
        chosen = rows[fitted]
        for o, value in zip(out, steps, strict=True):
            o[chosen] = value[chosen]
        slots = held[chosen]  # their envelope is the gap filter's too
        known[0][slots], known[1][slots], known[2][slots] = True, env[0, chosen], env[1, chosen]
        return rows[~fitted]

    def _room(self, slots: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Where each mover may stop, given its neighbours' current brake envelopes
        (computed for the whole group once per envelope)."""
        env = self._envelope()
        if self._room_of is not env:
            lo, hi = env
            pairs = self._pairs()
            room_hi, room_lo = np.full(lo.size, np.inf), np.full(lo.size, -np.inf)
            room_hi[pairs.succ] = lo[pairs.pred] + pairs.offset - pairs.gap
            if pairs.both:  # a mover moving back stops in front of its successor's envelope
                room_lo[pairs.pred] = hi[pairs.succ] + pairs.gap - pairs.offset
            t = np.flatnonzero(pairs.on_tcp(np.arange(pairs.succ.size)))
            if t.size:  # gaps on a TCP path (D-073)
                room_hi[pairs.succ[t]] = pairs.behind(t, lo[pairs.pred[t]] + pairs.offset[t])
                if pairs.both:
                    room_lo[pairs.pred[t]] = pairs.ahead(t, hi[pairs.succ[t]]) - pairs.offset[t]
            self._room_all = (room_hi, room_lo)
            self._room_of = env
        room_hi, room_lo = self._room_all
        return room_hi[slots], room_lo[slots]

    def _events(self, now: float) -> None:
        k = self.kernel
        self._end_profiles(np.flatnonzero((self.mode == FOLLOW)
                                          & (k.segments.end[self.rows] <= now)))
        held = np.flatnonzero(self.mode == HELD)
        if held.size:
            self._resume(held)
        self._after_resume(now)

    def _end_profiles(self, ended: np.ndarray) -> None:
        """Movers whose profile ended: done, idle, or held at a queue position."""
        for slot in ended.tolist():
            mover = self.movers[slot]
            if mover.job is None:
                self.mode[slot] = IDLE
            elif mover.job.kind == HALT or self.goal[slot] == mover.job.target:
                self._finish_job(mover)
            else:
                self.mode[slot] = HELD  # a queue position: wait for the way to clear

    def _after_resume(self, now: float, idle: bool | None = None) -> None:
        """Standby gap control and the group commands' ends, after the movers' events;
        ``idle``: whether no mover has a command, when the caller knows."""
        standby = self.parameters.standby_gap_control or self.parameters.active_gap_establishing
        if standby:
            self._restore_gaps()
        if idle is None or standby:  # standby gap control may have started jobs
            idle = no_command(self.mode)
        if self._halt is not None:
            if any(part.aborted for part in self._halt_parts):  # a new command took over
                self._halt.end(CommandStatus.ABORTED, now,
                                message="a member took another command")
                self._halt = None
            elif all(part.done for part in self._halt_parts) and idle:
                self._halt.end(CommandStatus.DONE, now)  # after standby opened the gaps (T8)
                self._halt = None
        if self._stop is not None:
            if self._stop.busy and idle:
                self._stop.status = CommandStatus.DONE
                self._stop.ended_at = now
            if self._stop.done and not self._stop.hold:
                self._stop = None
                self.state = GroupState.STANDBY
        if self.state is GroupState.MOVING and idle and self.all_axes_standing:
            self.state = GroupState.STANDBY

    def _resume(self, held: np.ndarray) -> None:
        """Held movers get a profile again: to the target once nothing can block it, or to
        the queue position once the neighbour in its way stands. Decided for all held movers
        at once; only the few that replan cost a ruckig call."""
        room_hi, room_lo = self._room(held)
        target, p = self.target[held], self.p[held]
        halting = self.halting[held]
        forward = target >= p
        free = ~halting & (room_lo <= target) & (target <= room_hi)
        other = np.where(forward, self.pred[held], self.succ[held])
        other_rests = other < 0
        has = ~other_rests
        other_rests[has] = self._resting(other[has])
        look = np.flatnonzero(halting | free | other_rests)  # only these can change now
        if not look.size:
            return
        held, target, p, halting, forward, free, other_rests, room_lo, room_hi = (
            x[look] for x in (held, target, p, halting, forward, free, other_rests, room_lo,
                              room_hi))
        lo, hi = self._envelope()
        rest = self._resting(held)
        goal = np.minimum(np.maximum(target, room_lo), room_hi)
        queue = ~halting & ~free & other_rests
        # no closer to the target (CA never moves a mover back, §3)
        queue &= ~(rest & (((goal - p) * (target - p) <= 0.0) | (np.abs(goal - p) <= TOLERANCE)))
        # cannot stop there any more (a pair that started too close)
        queue &= np.where(forward, hi[held] <= goal + TOLERANCE, lo[held] >= goal - TOLERANCE)
        # head on: both want the same room; the mover moving forwards takes it
        queue &= forward | ~self._head_on(held)
        for slot in held[halting & rest].tolist():
            self._finish_job(self.movers[slot])
        goals = np.where(free, target, goal)
        candidates = np.flatnonzero(free | queue)
        limits: dict[int, Limits] = {}
        if candidates.size:  # a profile with the command's limits must be able to stop there
            slots = held[candidates]
            vmax, acc, dec, jerk = self.lim.take(slots, axis=1)
            onward, there = forward[candidates], goals[candidates]
            fits = self._can_stop(slots, onward, there, vmax, acc, dec, jerk)
            # one that gap control braked beyond its command's dynamics stops at its queue
            # place with its hardest ones, not short of it to start again (D-210)
            u, b = np.where(onward, self.v[slots], -self.v[slots]), \
                np.where(onward, self.a[slots], -self.a[slots])
            hard = queue[candidates] & ~fits & ((b < -dec) | (u + b * np.abs(b) / (2.0 * jerk)
                                                               < 0.0))
            if hard.any():
                bdec, bjerk = self.bdec[slots], self.bjerk[slots]
                hard[hard] = self._can_stop(slots[hard], onward[hard], there[hard], vmax[hard],
                                            acc[hard], bdec[hard], bjerk[hard])
                for i in np.flatnonzero(hard).tolist():
                    limits[int(candidates[i])] = Limits(float(vmax[i]), float(acc[i]),
                                                        float(bdec[i]), float(bjerk[i]))
            candidates = candidates[fits | hard]
        for i in candidates.tolist():
            self._replan(self.movers[int(held[i])], float(goals[i]), limits.get(i))

    def _can_stop(self, slots: np.ndarray, forward: np.ndarray, goals: np.ndarray,
                  vmax: np.ndarray, acc: np.ndarray, dec: np.ndarray,
                  jerk: np.ndarray) -> np.ndarray:
        """Whether a profile with these limits can take each mover to rest at its goal: the
        state is within them and their brake stops before the goal without turning round."""
        step = np.where(forward, 1.0, -1.0)
        b = step * self.a[slots]
        c_lo, c_hi = brake_envelope(self.p[slots], self.v[slots], self.a[slots], dec, jerk)
        fits = np.where(forward, c_hi <= goals + TOLERANCE, c_lo >= goals - TOLERANCE)
        fits &= (b <= acc * FIT_SLACK) & (b >= -dec * FIT_SLACK)
        u = step * self.v[slots]  # and stop without turning round
        fits &= (u >= 0.0) & (u + b * np.abs(b) / (2.0 * jerk) >= -REST_SHARE * vmax)
        fits &= np.abs(self.v[slots]) <= vmax * FIT_SLACK
        return fits

    def _restore_gaps(self) -> None:
        """Standby gap control (§6, §8.1.1): movers without a command give way.

        An idle mover closer to its predecessor than its last valid gap moves back to it with
        the group's default dynamics; idle movers behind it move back as far as that needs
        (the push goes down the row). Movers with a command never give way.

        With direction Positive the successor alone keeps the gap (§8.1.3): a predecessor
        moving back is not held, so a mover without a command gives way to where the
        predecessor's command takes it, not only to where it stands, and a mover that gives
        way already goes further back when that place moves further back (D-208).
        """
        idle = self.mode == IDLE
        halting = self._halt is not None and not all(p.done for p in self._halt_parts)
        if self.state is GroupState.STOPPING or halting:
            return
        if self.parameters.gap_control_direction is GapControlDirection.POSITIVE:
            self._give_way(idle)
            return
        if not idle.any():
            return
        slots = np.flatnonzero(idle)
        room_hi, _ = self._room(slots)
        if not np.any(self.p[slots] > room_hi + STANDBY_DISTANCE):
            return
        lo, _hi = self._envelope()
        desired = self._push(idle, np.where(idle, self.p, lo))
        for slot in np.flatnonzero(idle & (desired < self.p - STANDBY_DISTANCE)).tolist():
            self._standby(self.movers[slot], float(desired[slot]))

    def _give_way(self, idle: np.ndarray) -> None:
        """Standby gap control with direction Positive (D-208): idle movers and those giving
        way already make room for the lowest point of their predecessor's brake and of the
        rest of its command (its profile's goal, or a held mover's target)."""
        giving = (self.mode == FOLLOW) & np.array(
            [m.job is not None and m.job.kind == STANDBY for m in self.movers], dtype=bool)
        free = idle | giving
        if not free.any():
            return
        lo, _hi = self._envelope()
        planned = np.where(self.mode == FOLLOW, self.goal,
                           np.where(self.mode == HELD, self.target, np.inf))
        low = np.where(free, np.where(idle, self.p, self.goal), np.minimum(lo, planned))
        pairs = self._pairs()
        m = np.flatnonzero(free[pairs.succ])
        if not m.size:
            return
        s = pairs.succ[m]
        limit = low[pairs.pred[m]] + pairs.offset[m] - pairs.gap[m]
        tcp = pairs.on_tcp(m)
        if tcp.any():  # gaps on a TCP path (D-073)
            limit[tcp] = pairs.behind(m[tcp], low[pairs.pred[m[tcp]]] + pairs.offset[m[tcp]])
        if not np.any(low[s] > limit + STANDBY_DISTANCE):
            return
        desired = self._push(free, low)
        for slot in np.flatnonzero(free & (desired < low - STANDBY_DISTANCE)).tolist():
            self._standby(self.movers[slot], float(desired[slot]))

    def _push(self, free: np.ndarray, desired: np.ndarray) -> np.ndarray:
        """Where each mover may end up at most: the ``free`` ones one gap behind where their
        predecessor may, down the row until nothing changes (a ring too)."""
        desired = desired.copy()
        order = list(range(len(self.movers)))
        for _ in range(len(order)):
            changed = False
            for slot in order:
                k = int(self.pred[slot])
                if k < 0 or not free[slot] or self.gmode[slot] == GapControlMode.NONE:
                    continue
                limit = self._behind(slot, desired[k] + self.offset[slot])
                if limit < desired[slot] - TOLERANCE:
                    desired[slot] = limit
                    changed = True
            if not changed:
                break
        return desired

    def _behind(self, slot: int, ahead: float) -> float:
        """Where ``slot`` stands one gap behind the motor position ``ahead`` of its
        predecessor: on the motor path, or on its template's TCP path (D-073)."""
        pairs = self._pairs()
        m = np.flatnonzero(pairs.succ == slot)
        if m.size and pairs.on_tcp(m)[0]:
            return float(pairs.behind(m, np.array([ahead]))[0])
        return ahead - float(self.gap[slot])

    def _standby(self, mover: Mover, target: float) -> None:
        p, group = mover.axis.parameters, self.parameters
        limits = Limits(min(group.default_velocity, p.max_velocity),
                        min(group.default_acceleration, p.max_acceleration),
                        min(group.default_deceleration, p.max_deceleration),
                        min(group.default_jerk, p.max_jerk))
        job = CaJob(STANDBY, self._command("standby_gap_control"), limits, mover.gap,
                    self.parameters.default_gap_control_mode, target_of=lambda _start: target)
        self._start(mover, job)

    def _resting(self, slots: np.ndarray) -> np.ndarray:
        """At rest up to float residue of the tracking steps."""
        vmax, acc = self.lim[0].take(slots), self.lim[1].take(slots)
        return (np.abs(self.v[slots]) <= REST_SHARE * vmax) & (
            np.abs(self.a[slots]) <= REST_SHARE * acc)

    def _replan(self, mover: Mover, goal: float, limits: Limits | None = None) -> None:
        """A profile to ``goal`` with the command's limits (or ``limits``): FOLLOW again."""
        slot = mover.slot
        job = mover.job
        assert job is not None
        start = KinematicState(float(self.p[slot]), float(self.v[slot]), float(self.a[slot]))
        try:
            profile = plan_position(start, goal, limits or job.limits)
        except CommandRejected:
            return  # stay held; the tracking step goes on
        self.kernel.segments.install(mover.axis.row, profile, self.runtime.now)
        self.mode[slot] = FOLLOW
        self.goal[slot] = goal
