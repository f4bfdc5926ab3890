"""Analyses of a derived system (docs/analysis.md), one module per concept:

    operating_point   the point: --at values, independent coordinates/speeds, manifold solve
    jacobians         matrices and exact Jacobians along common subexpressions, compiled
    linearize         the linear model A, B and M, C, K on the constraint manifold
    symbolic          symbolic A, B of small unconstrained systems
    stability         eigenvalues, modes, the verdict
    sweep             linearization along one variable; critical values
    equilibria        q' = 0: stationary points of V - T0 (with multipliers)
    routh             Routhian, effective potential, steady motions
    hamiltonian       momenta, H, Hamilton's equations
    report            text / JSON / LaTeX of all of the above
"""
