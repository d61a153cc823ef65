"""railcontact.core.status: one typed convergence status, combined over the parts of a result."""

from railcontact.core.status import SolverStatus


def test_defaults_and_failed():
    ok = SolverStatus()
    assert ok.converged and ok.message == "" and ok.iterations == 0 and ok.warnings == ()
    bad = SolverStatus.failed("residual 3e-3 > 1e-6", iterations=50.0, warnings=["w"])
    assert not bad.converged and bad.iterations == 50 and isinstance(bad.iterations, int)
    assert bad.warnings == ("w",)


def test_with_warnings_drops_duplicates_and_empties():
    s = SolverStatus(warnings=("a",)).with_warnings("b", "a", "", "c")
    assert s.warnings == ("a", "b", "c") and s.converged


def test_combine_labels_sums_and_skips_none():
    normal = SolverStatus(True, "", 7, ("grid truncates the contact",))
    tang = SolverStatus.failed("", 40)
    balance = SolverStatus.failed("no bracket", 3, ("grid truncates the contact",))
    whole = SolverStatus.combine([("normal", normal), ("tangential", tang), ("x", None),
                                  ("balance", balance)])
    assert not whole.converged
    assert whole.iterations == 50
    assert whole.message == "tangential: not converged; balance: no bracket"
    assert whole.warnings == ("normal: grid truncates the contact",
                              "balance: grid truncates the contact")
    assert SolverStatus.combine([("a", SolverStatus()), ("b", None)]) == SolverStatus()
    assert SolverStatus.combine([]).converged
    # an unlabelled part keeps its text as it is
    assert SolverStatus.combine([("", SolverStatus(warnings=("w", "w")))]).warnings == ("w",)


def test_to_dict_is_json_ready():
    d = SolverStatus.failed("m", 2, ("w",)).to_dict()
    assert d == {"converged": False, "message": "m", "iterations": 2, "warnings": ["w"]}
