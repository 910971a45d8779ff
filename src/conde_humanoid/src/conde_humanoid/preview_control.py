"""Centre-of-mass pattern from a zero-moment-point reference: the cart-table (linear inverted
pendulum) model with Kajita's preview controller, free of ROS.

Per horizontal axis the state is (CoM position [m], velocity [m/s], acceleration [m/s^2]), the
input the jerk [m/s^3], the output the ZMP p = x - (z_c / g) * x''. The gains minimise
sum(Qe (p - p_ref)^2 + R u^2): state feedback K from the discrete algebraic Riccati equation
(scipy.linalg.solve_discrete_are) and preview gains f_j on the next N reference samples.
Assumes a constant CoM height z_c and no angular momentum about the CoM.
"""

import numpy as np
from scipy.linalg import solve_discrete_are

GRAVITY_M_S2 = 9.81


class PreviewController:
    def __init__(self, com_height_m, dt_s, preview_s=1.6, qe=1.0, r=1e-6):
        if com_height_m <= 0 or dt_s <= 0 or preview_s < dt_s:
            raise ValueError('need com_height_m > 0, dt_s > 0, preview_s >= dt_s')
        self.dt_s = dt_s
        self.a = np.array([[1, dt_s, dt_s ** 2 / 2], [0, 1, dt_s], [0, 0, 1]])
        self.b = np.array([[dt_s ** 3 / 6], [dt_s ** 2 / 2], [dt_s]])
        self.c = np.array([[1, 0, -com_height_m / GRAVITY_M_S2]])
        p = solve_discrete_are(self.a, self.b, qe * self.c.T @ self.c, np.array([[r]]))
        gain = np.linalg.inv(r + self.b.T @ p @ self.b)
        self.k = (gain @ self.b.T @ p @ self.a).ravel()
        self.preview_steps = int(round(preview_s / dt_s))
        closed = (self.a - self.b @ self.k[None, :]).T
        x = self.c.T * qe
        f = []
        for _ in range(self.preview_steps):
            f.append((gain @ self.b.T @ x).item())
            x = closed @ x
        self.f = np.array(f)

    def run(self, zmp_ref_m, x0_m=None):
        """CoM positions [m] and ZMPs [m] (arrays as long as `zmp_ref_m`) tracking the reference;
        past its end the reference holds its last value. Starts at rest at `x0_m` (default the
        first reference)."""
        ref = np.asarray(zmp_ref_m, dtype=float)
        padded = np.concatenate([ref, np.full(self.preview_steps + 1, ref[-1])])
        x = np.array([ref[0] if x0_m is None else x0_m, 0.0, 0.0])
        com, zmp = np.empty(len(ref)), np.empty(len(ref))
        for k in range(len(ref)):
            com[k] = x[0]
            zmp[k] = (self.c @ x).item()
            u = -self.k @ x + self.f @ padded[k + 1:k + 1 + self.preview_steps]
            x = self.a @ x + self.b.ravel() * u
        return com, zmp
