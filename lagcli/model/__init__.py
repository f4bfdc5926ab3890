"""Model building: a checked `Spec` -> the sympy `Model` the derivation reads.

    build.py        build_model(spec) -> Model (model_types.py: the Model and its parts)
    expr.py         the safe expression parser (never eval/sympify of spec text)
    calculus.py     derivatives and simplification rules; constants.py: bounded evaluation
    products.py, sums.py, ordering.py   sympy's Mul, Add and argument order, built directly
    collector.py    the cycle collector paused while big expressions are built
    vectors.py      frames and vectors -> scalar components; kinematics.py: rotations
    rolling.py      rolling contacts -> constraint rows
    symbols.py      q_dot / q_ddot symbols (printed as q-dot in LaTeX)
    units.py        dimensions of a spec with units; validation.py: masses, inertias, ...
"""
