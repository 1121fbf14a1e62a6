"""Known-answer tests of hippo/perception/context_tree.py: ContextParams' defaults and bounds
(each exactly on its edge and one step past, every error word for word), the G-test on tables
worked out by hand and against scipy's own log-likelihood test, and the suffix-tree nodes'
routing."""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.stats import chi2, chi2_contingency

from hippo.perception.context_tree import ContextKey, ContextParams, _Inst, _Node, g_test


# ------------------------------------------------------------------------------ ContextParams
def test_context_params_defaults_are_the_documented_ones():
    # the values the class docstring gives
    p = ContextParams()
    assert (p.max_depth, p.min_count, p.alpha, p.alpha_merge) == (3, 6, 1e-3, 0.05)
    assert (p.dwell_tolerance, p.weber, p.memory, p.merge_horizon) == (0.5, 0.1, 256, 8)
    assert p.merge_places is True and p.merge_bypasses is True


@pytest.mark.parametrize("kw", [
    {"max_depth": 0}, {"min_count": 2}, {"merge_horizon": 1},
    {"alpha": 1e-300}, {"alpha": 0.5, "alpha_merge": float(np.nextafter(1.0, 0.0))},
    {"alpha": 0.2, "alpha_merge": 0.2},          # alpha_merge == alpha: allowed
    {"dwell_tolerance": 0.0}, {"weber": 1e-300},
    {"min_count": 6, "memory": 12},              # memory exactly 2 * min_count
    {"min_count": 2, "memory": 4},
])
def test_context_params_accept_their_edges(kw):
    p = ContextParams(**kw)
    for k, v in kw.items():
        assert getattr(p, k) == v


@pytest.mark.parametrize(("kw", "msg"), [
    ({"max_depth": -1}, "max_depth must be an integer >= 0, got -1"),
    ({"min_count": 1}, "min_count must be an integer >= 2, got 1"),
    ({"alpha": 0.0}, "alpha must lie in (0.0, 1.0), got 0.0"),
    ({"alpha": 1.0}, "alpha must lie in (0.0, 1.0), got 1.0"),
    ({"alpha_merge": 0.0}, "alpha_merge must lie in (0.0, 1.0), got 0.0"),
    ({"alpha_merge": 1.0}, "alpha_merge must lie in (0.0, 1.0), got 1.0"),
    ({"alpha": 0.1, "alpha_merge": 0.01}, "alpha_merge (0.01) must be >= alpha (0.1)"),
    ({"alpha": 0.2, "alpha_merge": float(np.nextafter(0.2, 0.0))},
     f"alpha_merge ({float(np.nextafter(0.2, 0.0))}) must be >= alpha (0.2)"),
    ({"dwell_tolerance": -0.5}, "dwell_tolerance must be finite and >= 0, got -0.5"),
    ({"weber": 0.0}, "weber must be finite and > 0, got 0.0"),
    ({"merge_horizon": 0}, "merge_horizon must be an integer >= 1, got 0"),
    ({"min_count": 6, "memory": 11}, "memory must be an integer >= 2 * min_count (12), got 11"),
    ({"min_count": 3, "memory": 5}, "memory must be an integer >= 2 * min_count (6), got 5"),
    ({"max_depth": 1.5}, "ContextParams.max_depth must be"),
    ({"min_count": True}, "ContextParams.min_count must be"),
])
def test_context_params_refuse_one_step_past_each_edge(kw, msg):
    with pytest.raises(ValueError) as err:
        ContextParams(**kw)
    assert str(err.value).startswith(msg)
    if not msg.startswith("ContextParams."):
        assert str(err.value) == msg


# ------------------------------------------------------------------------------ g_test
def test_g_test_on_tables_worked_out_by_hand():
    # [[2, 1], [1, 2]]: margins 3, 3, 3, 3 of 6, every E = 1.5;
    # G = 2 (2 * 2 ln(2 / 1.5) + 2 * 1 ln(1 / 1.5)), one degree of freedom
    g = 2 * (4 * math.log(4 / 3) + 2 * math.log(2 / 3))
    assert g_test([[2, 1], [1, 2]]) == pytest.approx(chi2.sf(g, 1), rel=1e-12)
    # [[4, 0, 2], [0, 4, 2]]: every E = 6 * 4 / 12 = 2, G = 2 (4 ln 2 + 4 ln 2) = 16 ln 2 on
    # (2 - 1)(3 - 1) = 2 degrees of freedom, whose survival function is exp(-G / 2) = 2^-8
    assert g_test([[4, 0, 2], [0, 4, 2]]) == pytest.approx(2.0**-8, rel=1e-12)
    assert g_test([[4, 0], [0, 4], [2, 2]]) == pytest.approx(2.0**-8, rel=1e-12)  # transposed
    # [[1, 0], [0, 3]]: rows and columns of 1 and 3 counts, E11 = 1 * 1 / 4, E22 = 3 * 3 / 4;
    # G = 2 (1 ln 4 + 3 ln(4 / 3)) on one degree of freedom (a row or column of one count counts)
    g = 2 * (math.log(4) + 3 * math.log(4 / 3))
    assert g_test([[1, 0], [0, 3]]) == pytest.approx(chi2.sf(g, 1), rel=1e-12)
    assert g_test([[0, 1], [3, 0]]) == pytest.approx(chi2.sf(g, 1), rel=1e-12)
    # identical rows: G = 0, p = 1
    assert g_test([[3, 1, 2], [3, 1, 2]]) == pytest.approx(1.0, abs=1e-12)


def test_g_test_agrees_with_scipys_log_likelihood_test():
    rng = np.random.default_rng(0)
    for shape in ((2, 2), (2, 3), (3, 4), (4, 2)):
        for _ in range(5):
            t = rng.integers(1, 12, size=shape)
            _, p, dof, _ = chi2_contingency(t, correction=False, lambda_="log-likelihood")
            assert dof == (shape[0] - 1) * (shape[1] - 1)
            assert g_test(t) == pytest.approx(p, rel=1e-9)


def test_g_test_counts_in_double_precision_whatever_the_tables_dtype():
    # counts stored as float16 (exact below 2048) give the test of the same integer counts;
    # their margins (2101) and products (~4.4e6) do not fit float16
    t = np.array([[1001, 1100], [1000, 1101]])
    _, p, _, _ = chi2_contingency(t, correction=False, lambda_="log-likelihood")
    assert g_test(t.astype(np.float16)) == pytest.approx(p, rel=1e-9)
    assert g_test(t.astype(np.uint16)) == pytest.approx(p, rel=1e-9)


def test_g_test_drops_empty_rows_and_columns():
    # the empty row and column carry nothing: the test is the one of [[3, 1], [1, 3]]
    _, p, _, _ = chi2_contingency([[3, 1], [1, 3]], correction=False, lambda_="log-likelihood")
    assert g_test([[3, 0, 1], [0, 0, 0], [1, 0, 3]]) == pytest.approx(p, rel=1e-12)
    # what is left has one row or one column: nothing to test
    assert g_test([[5, 0], [0, 0]]) == 1.0
    assert g_test([[5, 2], [0, 0]]) == 1.0
    assert g_test([[5, 0], [2, 0]]) == 1.0
    assert g_test([[1, 2, 3]]) == 1.0
    assert g_test([[1], [2], [3]]) == 1.0
    assert g_test(np.zeros((3, 3))) == 1.0


@pytest.mark.parametrize("table", [
    [1, 2], [[[1, 2], [3, 4]]], [[1, -1], [0, 2]], [[1, math.nan], [1, 1]],
    [[1, math.inf], [1, 1]], 3,
])
def test_g_test_refuses_what_is_not_a_table_of_counts(table):
    with pytest.raises(ValueError) as err:
        g_test(table)
    assert str(err.value) == f"table must be a 2-D array of counts >= 0, got {table!r}"


# ------------------------------------------------------------------------------ the tree
def test_a_node_is_a_leaf_exactly_when_it_has_a_context_id():
    assert _Node(0, cid=0).leaf and _Node(2, cid=5).leaf
    n = _Node(1)
    assert not n.leaf and n.pos == -1 and n.route == {} and n.default is None
    assert _Node(0).route is not _Node(0).route  # each node its own routing table


def test_a_node_routes_by_one_step_of_history_read_through_same():
    a, b, d = _Node(2, cid=1), _Node(2, cid=2), _Node(2, cid=3)
    n = _Node(0, pos=1, route={"A": a, "B": b}, default=d)
    same = {"A2": "A"}.get
    # the place pos + 1 = 2 steps back decides
    assert n.step(("X", "A"), lambda q: q) is a
    assert n.step(("X", "B", "Z"), lambda q: q) is b
    assert n.step(("X", "A2"), lambda q: same(q, q)) is a   # a merged place: its state's child
    assert n.step(("X", "C"), lambda q: q) is d             # never seen: the default
    # a history of exactly pos + 1 places is routed; one of pos places goes to the default
    assert n.step(("X",), lambda q: q) is d
    assert n.step((), lambda q: q) is d
    assert n.child("A") is a and n.child("nope") is d


def test_a_nodes_children_are_listed_once_routes_first():
    a, b = _Node(1, cid=1), _Node(1, cid=2)
    n = _Node(0, pos=0, route={"A": a, "A2": a, "B": b}, default=a)
    assert n.children() == [a, b]
    d = _Node(1, cid=3)
    n.default = d
    assert n.children() == [a, b, d]
    n.default = None
    assert n.children() == [a, b]
    # equal nodes that are not the same object are both children (identity, not equality)
    e1, e2 = _Node(1, cid=7), _Node(1, cid=7)
    assert _Node(0, pos=0, route={"A": e1}, default=e2).children() == [e1, e2]
    assert len(_Node(0, pos=0, route={"A": e1}, default=e2).children()) == 2


def test_keys_and_instances_keep_their_fields():
    k = ContextKey("C", ((2, frozenset({"A"})),))
    assert k.place == "C" and k.history == ((2, frozenset({"A"})),)
    i = _Inst(("B", "A"), "D", 2.5, ["D"], [])
    assert (i.history, i.next, i.dwell, i.future, i.future_dwell) == (("B", "A"), "D", 2.5,
                                                                     ["D"], [])
