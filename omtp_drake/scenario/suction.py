"""A vacuum gripper's settings (part of the scenario YAML schema).

The gripper systems that apply them live in :mod:`omtp_drake.cell.suction` (the attach
rule) and :mod:`omtp_drake.cell.suction_holds` (the two ways of holding a part).
"""

import math
from collections.abc import Callable
from dataclasses import dataclass

from omtp_drake.errors import MAX_RATE_HZ, ConfigError

#: The two ways of holding a part.
BACKENDS = ("weld", "force")


@dataclass
class SuctionConfig:
    """Parameters of one vacuum gripper (part of the scenario YAML schema).

    Attributes:
        backend: ``"weld"`` (rigid distance constraints synced by the runtime,
            see :func:`sync_weld`) or ``"force"`` (a spring-damper force inside
            the diagram).
        check_rate_hz: rate of the contact checks of an enabled gripper, on
            simulated time [Hz]; in [10, 1000]. The first check runs at the
            first plant step after the gripper is enabled, the next ones every
            ``1 / rate`` after it: the course's plugin checks at the first
            physics update after it is enabled and then every 0.1 s (its
            ``updateRate``), so 10 by default. A disable is seen at the next
            plant step, as the plugin detaches at its next physics update.
        max_angle_deg: largest angle between the contact normal and the tool
            axis (+Cz) for a touch to count [deg]; in (0, 90).
        consecutive_checks: number of consecutive good checks (same part
            touching, within the angle) that attach it; >= 1 (course: 2).
        stiffness: force backend, translational stiffness [N/m].
        damping: force backend, translational damping [N s/m].
        angular_stiffness: force backend, rotational stiffness [N m/rad].
        angular_damping: force backend, rotational damping [N m s/rad].
        apply_reaction: force backend: also apply the equal and opposite
            wrench to the cup. Off by default: the spring is explicit, and on a
            UR10 whose light wrist is driven by an (explicit)
            InverseDynamicsController the reaction blew the simulation up
            (NaN within 2 s, both 0.2 and 1 kg parts); without it the part is
            carried stably (0.5-0.8 mm drift at about 1 m/s) but the arm does
            not feel the load (its controller's model does not include the
            part either). Turn it on only for a cup carried by a stiff,
            implicitly controlled mechanism (e.g. SAP joint PD), where it is
            stable and conserves momentum.
        max_hold_distance: if the part's centre is ever found this far [m]
            from its captured pose in the cup (at a check), the hold is lost:
            ``attached`` becomes false (a "hold lost" release). Mostly a force
            backend event (a rigid weld does not let go).

    Force gains. The spring acts explicitly (evaluated once per plant step
    of length h), so it is stable only while ``k h^2 / m`` and ``c h / m`` stay
    small for the part's mass m (and likewise with the rotational inertia).
    The gripper therefore caps the gains per part at the deadbeat values
    ``k <= m / h^2``, ``c <= m / h`` (and ``I / h^2``, ``I / h`` for the
    rotational ones, I the smallest principal moment about the centre of
    mass), where the discrete error dies out in two steps. The defaults are
    chosen for parts of 0.2 to 1 kg (0.2 m cubes) at h = 2 ms; at the default
    h = 10 ms every part of the course runs at its caps:

    ======  ==============================  ==============================
    mass    k [N/m], c [N s/m] used         kr [N m/rad], cr [N m s/rad]
    ======  ==============================  ==============================
    0.2 kg  2e3, 20 (both capped)           13, 0.13 (both capped)
    0.5 kg  5e3, 50 (both capped)           33, 0.33 (both capped)
    1 kg    1e4, 100 (both capped)          67, 0.67 (both capped)
    ======  ==============================  ==============================

    Static sag is about m g / k = g h^2 (1 mm at the caps) and a h^2 under an
    acceleration a (2 mm at 20 m/s^2). Measured carrying 1 kg at 1 m/s with
    20 m/s^2 ramps (``bench/bench_step.py``): 2.9 mm worst drift at 10 ms, 0.8 mm
    at 5 ms (weld: 14 and 4 um). For a force-held part that must stay within
    1 mm, run the plant at 5 ms (``plant_config: {time_step: 0.005}``).
    """

    backend: str = "weld"
    check_rate_hz: float = 10.0
    max_angle_deg: float = 18.0
    consecutive_checks: int = 2
    stiffness: float = 1e5
    damping: float = 400.0
    angular_stiffness: float = 1000.0
    angular_damping: float = 2.5
    apply_reaction: bool = False
    max_hold_distance: float = 0.02

    def validate(self) -> None:
        """Raises :class:`ConfigError` naming the field, its value and the valid range."""
        if self.backend not in BACKENDS:
            raise ConfigError(f"suction.backend must be one of {', '.join(BACKENDS)}; got {self.backend!r}")
        _check(
            self.check_rate_hz,
            "check_rate_hz",
            f"[10, {MAX_RATE_HZ:g}] Hz",
            lambda x: 10.0 <= x <= MAX_RATE_HZ,
        )
        _check(self.max_angle_deg, "max_angle_deg", "(0, 90) deg", lambda x: 0.0 < x < 90.0)
        if (
            isinstance(self.consecutive_checks, bool)
            or not isinstance(self.consecutive_checks, int)
            or self.consecutive_checks < 1
        ):
            raise ConfigError(
                f"suction.consecutive_checks must be an integer >= 1; got {self.consecutive_checks!r}"
            )
        for name, unit in (("stiffness", "N/m"), ("angular_stiffness", "N m/rad")):
            _check(getattr(self, name), name, f"(0, inf) {unit}", lambda x: 0.0 < x < math.inf)
        for name, unit in (("damping", "N s/m"), ("angular_damping", "N m s/rad")):
            _check(getattr(self, name), name, f"[0, inf) {unit}", lambda x: 0.0 <= x < math.inf)
        _check(self.max_hold_distance, "max_hold_distance", "(0, inf) m", lambda x: 0.0 < x < math.inf)
        if not isinstance(self.apply_reaction, bool):
            raise ConfigError(f"suction.apply_reaction must be true or false; got {self.apply_reaction!r}")


def _check(value: object, name: str, valid: str, ok: Callable[[float], bool]) -> None:
    try:
        x = float(value)  # type: ignore[arg-type]
    except (TypeError, ValueError):
        raise ConfigError(f"suction.{name} must be a number in {valid}; got {value!r}") from None
    if isinstance(value, bool) or math.isnan(x) or not ok(x):
        raise ConfigError(f"suction.{name} must be in {valid}; got {value!r}")
