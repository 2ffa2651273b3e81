"""Physically consistent identification of a robot's and a payload's inertial parameters (beyond the paper:
Section 2's f(Phi) > 0 and Property 2's M a + C v + G = sum_l R_l Phi_l, read as an identification problem)."""
