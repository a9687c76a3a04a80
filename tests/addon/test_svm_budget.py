"""Apply material's note on the SVM stack (clothbake.core.svm_budget): the
count of light terms and the note exactly past the measured limit."""
from clothbake.core import svm_budget


def test_an_area_light_counts_two_terms():
    assert svm_budget.light_terms(["POINT", "SPOT", "AREA", "AREA"]) == 6
    assert svm_budget.light_terms([]) == 0


def test_the_world_counts_two_terms_on_cycles_lit():
    assert svm_budget.light_terms([], "cycles-lit") == 2
    assert svm_budget.light_terms(["AREA"], "cycles-lit") == 4
    assert svm_budget.light_terms(["AREA"], "exact") == 2


def test_the_note_starts_one_term_past_each_limit():
    for (colour_free, route), terms in svm_budget.LIGHT_TERM_LIMIT.items():
        limit = terms - svm_budget.WORLD_TERMS[route]     # lights' own terms
        assert svm_budget.stack_note(["POINT"] * limit, colour_free, route) is None
        note = svm_budget.stack_note(["POINT"] * (limit + 1), colour_free, route)
        assert note is not None and f"past {terms}" in note and route in note
        assert ("the world counts 2" in note) == (route == "cycles-lit")
        # One area light fewer point lights: the same terms, the same verdict.
        assert svm_budget.stack_note(["AREA"] + ["POINT"] * (limit - 2), colour_free,
                                     route) is None
        note = svm_budget.stack_note(["AREA"] + ["POINT"] * (limit - 1), colour_free, route)
        assert note is not None and "area light counts two" in note


def test_blender_5_has_its_own_limits():
    """5.x's limits (measured in 5.2.2): the exact route's edge is lower,
    and cycles-lit fits under no light at all; 3.x and 4.x keep 3.4's."""
    assert svm_budget.term_limit(True, "exact", (4, 3, 2)) == \
        svm_budget.LIGHT_TERM_LIMIT[(True, "exact")]
    limit = svm_budget.term_limit(True, "exact", (5, 2, 2))
    assert limit < svm_budget.LIGHT_TERM_LIMIT[(True, "exact")]
    assert svm_budget.stack_note(["POINT"] * limit, True, "exact", (5, 2, 2)) is None
    assert "past" in svm_budget.stack_note(["POINT"] * (limit + 1), True, "exact", (5, 2, 2))
    note = svm_budget.stack_note([], True, "cycles-lit", (5, 2, 2))
    assert note is not None and "use the exact route" in note and "Blender 5.2" in note
    assert "single light" in note
    assert svm_budget.stack_note(["POINT"], True, "cycles-lit", (4, 3, 2)) is None
