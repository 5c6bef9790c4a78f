"""Closed-form IK by subproblem decomposition, for any chain whose axes allow it (see docs/ik.md).

:mod:`.poe` puts a chain in product-of-exponentials form, :mod:`.subproblems` holds the
Paden-Kahan subproblems and IK-Geo's SP1-SP6, :mod:`.classify` names which axes meet or are
parallel and so which solver answers.
"""
