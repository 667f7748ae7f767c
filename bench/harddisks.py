"""Hard-disk physics shared by bench/event_physics.py and bench/accuracy.py:
Henderson's equation of state, the collision rate it implies, and the
Kolmogorov-Smirnov distance of speeds from Maxwell-Boltzmann in 2D."""
import math


def henderson(eta):
    """Z = PA / NkT of hard disks at area fraction eta (Henderson 1975)."""
    return (1 + eta * eta / 8) / (1 - eta) ** 2


def collision_rate(eta, kT, sigma=2.0):
    """Collisions per disk per unit time implied by Henderson's Z: in
    equilibrium the mean of -dr.dv over collisions is sigma sqrt(pi kT)
    (unit masses), so nu = 4 (Z - 1) sqrt(kT) / (sigma sqrt(pi))."""
    return 4 * (henderson(eta) - 1) * math.sqrt(kT) / (sigma * math.sqrt(math.pi))


def ks_maxwell(speeds, kT):
    """KS distance of the speeds from F(v) = 1 - exp(-v^2 / 2kT)."""
    v = sorted(speeds)
    n = len(v)
    d = 0.0
    for i, s in enumerate(v):
        F = 1 - math.exp(-s * s / (2 * kT))
        d = max(d, abs(F - i / n), abs(F - (i + 1) / n))
    return d
