"""Fuzzed loaders: real saved files mutated byte by byte and field by field.

Every loader must either load the file (and then give a usable object: finite outputs, a map
that saves again) or raise :class:`hippo.io.CorruptFileError`; any other exception is a crash.
The default run mutates ~1,000 files; ``-m slow`` mutates > 10,000
(``HIPPO_FUZZ_EXAMPLES`` sets the number per loader and mutation kind).
"""

from __future__ import annotations

import io as _io
import json
import math
import os
import tempfile
import xml.etree.ElementTree as ET
import zipfile
from collections.abc import Callable
from pathlib import Path

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from hippo.cognitive_map import DriveParams, Drives, TransitionGraph
from hippo.cognitive_map.synthetic import random_transition_graph
from hippo.io import CorruptFileError
from hippo.perception import RCSFAICA
from hippo.perception.ica import FastICA
from hippo.perception.prototypes import PlacePrototypes, PrototypeParams
from hippo.perception.reservoir import Reservoir
from hippo.perception.reservoir_params import ReservoirParams
from hippo.perception.sfa import SFA
from hippo.sim.record import Recording, record

QUICK = 25  # examples per (loader, mutation kind) in the default run
SLOW = int(os.environ.get("HIPPO_FUZZ_EXAMPLES", "700"))


# --------------------------------------------------------------------- real saved files
@pytest.fixture(scope="module")
def files(tmp_path_factory) -> dict[str, tuple[Path, Callable[[Path], object]]]:
    d = tmp_path_factory.mktemp("fuzz_src")
    rec = record("two_rooms", 400, seed=3)
    U = rec.sensors
    model = RCSFAICA(n_reservoir=20, ica_restarts=1).fit(U)
    plain = RCSFAICA(use_reservoir=False, n_sfa=3, n_ica=3, ica_restarts=1,
                     sfa_expansion="quadratic").fit(U)
    protos = PlacePrototypes(PrototypeParams(n_prototypes=6)).fit(model.transform(U))
    X = model.features(U)  # the parts alone: SFA on the reservoir's features, ICA on SFA's
    sfa = SFA(n_components=4).fit(X)
    sfa_quad = SFA(n_components=3, expansion="quadratic").fit(U)
    ica = FastICA(n_components=3, n_restarts=1).fit(sfa.transform(X))
    res = Reservoir(ReservoirParams(n_neurons=15, leak=(0.1, 0.3), seed=2))
    g = random_transition_graph(6, 12, np.random.default_rng(0))
    for s in range(4):
        g.observe_position(s, (10.0 * s, -3.0))
    g.add_transition(2, 2, "wait", 5.0)
    drives = Drives()
    drives.add("food", DriveParams(epsilon=0.02))
    drives.add("patrol")
    drives.set_level("food", 0.4)
    drives.reward("food", (0, 1))
    drives.reward("patrol", (2, 3), 0.5)

    def use_model(m: RCSFAICA) -> None:
        out = m.transform(U[:30])
        assert np.isfinite(out).all()
        m.reset_state()
        assert np.isfinite(m.step(U[0])).all()

    def use_protos(p: PlacePrototypes) -> None:
        y = np.zeros(p.centres_.shape[1])
        assert np.isfinite(p.step(y)).all()

    def use_sfa(s: SFA) -> None:
        assert np.isfinite(s.transform((U if s.params.expansion == "quadratic" else X)[:30])).all()

    def use_ica(i: FastICA) -> None:
        assert np.isfinite(i.transform(np.zeros((3, i.n_features_in_)))).all()

    def use_reservoir(r: Reservoir) -> None:
        assert np.isfinite(r.run(U[:20])).all() and np.isfinite(r.step(U[0])).all()

    def use_graph(h: TransitionGraph) -> None:
        for t in h:
            a = h.attributes(t)
            assert a["count"] >= 1 and 0.0 <= a["strength"] <= 1.0
            assert a["delay"] is None or (math.isfinite(a["delay"]) and a["delay"] >= 0)
        with tempfile.TemporaryDirectory() as tmp:
            assert TransitionGraph.from_graphml(h.to_graphml(Path(tmp) / "g.graphml")).same_as(h)

    def use_drives(dr: Drives) -> None:
        assert all(0.0 <= v <= 1.0 for v in dr.levels.values())
        try:
            dr.step(0.2)
        except ValueError as exc:  # a legal but fast rate (epsilon > 1/dt) needs a smaller dt
            assert "smaller dt" in str(exc)

    def use_rec(r: Recording) -> None:
        assert len(r.sensors) == len(r.t) == len(r.x)
        assert ((r.sensors >= 0) & (r.sensors <= 1)).all()

    out = {
        "rcsfaica": (model.save(d / "m.npz"), RCSFAICA.load, use_model),
        "rcsfaica_plain": (plain.save(d / "p.npz"), RCSFAICA.load, use_model),
        "prototypes": (protos.save(d / "proto.npz"), PlacePrototypes.load, use_protos),
        "sfa": (sfa.save(d / "sfa.npz"), SFA.load, use_sfa),
        "sfa_quad": (sfa_quad.save(d / "sfa_quad.npz"), SFA.load, use_sfa),
        "ica": (ica.save(d / "ica.npz"), FastICA.load, use_ica),
        "reservoir": (res.save(d / "res.npz"), Reservoir.load, use_reservoir),
        "recording": (rec.slice(0, 60).save(d / "rec.npz"), Recording.load, use_rec),
        "graph": (g.to_graphml(d / "g.graphml"), TransitionGraph.from_graphml, use_graph),
        "drives": (drives.save(d / "drives.json"), Drives.load, use_drives),
    }
    # the same npz contents stored uncompressed: byte flips then land in the array data
    for name in ("rcsfaica", "prototypes", "recording", "sfa", "ica", "reservoir"):
        path, loader, use = out[name]
        with np.load(path, allow_pickle=False) as z:
            arrays = {k: z[k] for k in z.files}
        raw = d / f"{name}_raw.npz"
        np.savez(raw, **arrays)
        out[f"{name}_raw"] = (raw, loader, use)
    for path, loader, use in out.values():  # the originals load and work
        use(loader(path))
    return out


MUTATED = {"files": 0}  # mutated files loaded so far (the slow test checks the total)


def _try_load(files, name: str, blob: bytes, suffix: str) -> None:
    MUTATED["files"] += 1
    _path, loader, use = files[name]
    with tempfile.TemporaryDirectory() as tmp:
        p = Path(tmp) / f"mutant{suffix}"
        p.write_bytes(blob)
        try:
            obj = loader(p)
        except CorruptFileError:
            return
        use(obj)  # loaded: it must work


# ----------------------------------------------------------------------- byte mutations
def _byte_mutation():
    return st.one_of(
        st.tuples(st.just("flip"), st.lists(st.tuples(st.floats(0, 1, exclude_max=True),
                                                      st.integers(0, 255)), min_size=1,
                                            max_size=8)),
        st.tuples(st.just("truncate"), st.floats(0, 1, exclude_max=True)),
        st.tuples(st.just("delete"), st.floats(0, 1, exclude_max=True), st.integers(1, 64)),
        st.tuples(st.just("insert"), st.floats(0, 1), st.binary(min_size=1, max_size=32)),
    )


def _mutate_bytes(blob: bytes, m) -> bytes:
    b = bytearray(blob)
    kind = m[0]
    if kind == "flip":
        for pos, val in m[1]:
            b[int(pos * len(b))] = val
    elif kind == "truncate":
        del b[int(m[1] * len(b)):]
    elif kind == "delete":
        i = int(m[1] * len(b))
        del b[i:i + m[2]]
    else:
        i = int(m[1] * len(b))
        b[i:i] = m[2]
    return bytes(b)


BYTE_TARGETS = ["rcsfaica", "rcsfaica_raw", "rcsfaica_plain", "prototypes", "prototypes_raw",
                "recording", "recording_raw", "graph", "drives", "sfa", "sfa_raw", "ica",
                "ica_raw", "reservoir", "reservoir_raw"]


def _byte_test(files, name: str, n: int) -> None:
    path = files[name][0]
    blob = path.read_bytes()

    @settings(max_examples=n, deadline=None, derandomize=True, database=None,
              suppress_health_check=list(HealthCheck))
    @given(_byte_mutation())
    def run(m):
        _try_load(files, name, _mutate_bytes(blob, m), path.suffix)

    run()


@pytest.mark.parametrize("name", BYTE_TARGETS)
def test_byte_mutations(files, name):
    _byte_test(files, name, QUICK)


# ---------------------------------------------------------------------- field mutations
_BAD_VALUES = st.sampled_from([
    np.nan, np.inf, -np.inf, -2.0, -1, 0, 1e300, -1e300, 2**70, 0.5, 3, "x", "", True, None,
])


def _npz_field_mutation():
    return st.tuples(
        st.integers(0, 10_000),  # which array (modulo the number of arrays)
        st.sampled_from(["delete", "nan", "inf", "scale", "negate", "shape_drop", "shape_add",
                         "transpose", "flatten", "scalar", "empty", "to_str", "to_bool",
                         "to_complex", "to_int", "to_object_str", "one_value", "zero"]),
        st.floats(0, 1, exclude_max=True), _BAD_VALUES,
    )


def _mutate_array(a: np.ndarray, how: str, where: float, value) -> np.ndarray | None:
    if how == "delete":
        return None
    if how in ("nan", "inf", "one_value") and a.size and a.dtype.kind in "fiu":
        b = a.astype(float).copy()
        flat = b.reshape(-1)
        flat[int(where * flat.size)] = {"nan": np.nan, "inf": np.inf}.get(
            how, value if isinstance(value, float | int) and not isinstance(value, bool)
            else -1.0)
        return b
    if how == "scale" and a.dtype.kind in "fiu":
        return a * 1e200
    if how == "negate" and a.dtype.kind in "fi":
        return -a
    if how == "zero" and a.dtype.kind in "fiu":
        return np.zeros_like(a)
    if how == "shape_drop" and a.ndim:
        return a[:-1] if a.shape[0] else a[..., None]
    if how == "shape_add" and a.ndim:
        return np.concatenate([a, a[:1]])
    if how == "transpose" and a.ndim == 2:
        return a.T.copy() if a.shape[0] != a.shape[1] else a[:, :-1]
    if how == "flatten":
        return a.reshape(-1)
    if how == "scalar":
        return np.array(a.reshape(-1)[0] if a.size else 0)
    if how == "empty":
        return a.reshape(-1)[:0]
    if how == "to_str":
        return np.array(str(value))
    if how == "to_bool":
        return np.asarray(a).astype(bool) if a.dtype.kind in "fiub" else np.array(True)
    if how == "to_complex" and a.dtype.kind in "fiu":
        return a.astype(complex)
    if how == "to_int" and a.dtype.kind in "fu":
        return a.astype(np.int64)
    if how == "to_object_str":
        return np.array(["a", "bc"])
    return np.array(value if value is not None else 0.0)


def _params_mutations():
    keys = st.sampled_from(["n_inputs", "n_reservoir", "leak", "spectral_radius", "n_sfa",
                            "n_ica", "use_reservoir", "sfa_expansion", "downsample", "seed",
                            "dtype", "device", "input_range", "out_of_range", "washout",
                            "not_a_param",
                            # the parts' own parameters
                            "n_components", "cutoff", "expansion", "algorithm", "whiten",
                            "n_neurons", "input_weight", "input_prob"])
    return st.tuples(keys, st.one_of(_BAD_VALUES, st.integers(-3, 700),
                                     st.lists(st.floats(allow_nan=True), max_size=3)))


def _npz_field_test(files, name: str, n: int) -> None:
    path, _loader, _use = files[name]
    with np.load(path, allow_pickle=False) as z:
        arrays = {k: z[k] for k in z.files}
    keys = sorted(arrays)

    @settings(max_examples=n, deadline=None, derandomize=True, database=None,
              suppress_health_check=list(HealthCheck))
    @given(_npz_field_mutation(), st.one_of(st.none(), _params_mutations()))
    def run(m, pm):
        idx, how, where, value = m
        mutated = dict(arrays)
        k = keys[idx % len(keys)]
        new = _mutate_array(arrays[k], how, where, value)
        if new is None:
            del mutated[k]
        else:
            mutated[k] = new
        if pm is not None and "params" in mutated and mutated["params"].dtype.kind == "U":
            try:
                raw = json.loads(str(mutated["params"]))
                raw[pm[0]] = pm[1]
                mutated["params"] = np.array(json.dumps(raw))
            except (ValueError, TypeError, AttributeError):
                pass
        buf = _io.BytesIO()
        np.savez(buf, **mutated)
        _try_load(files, name, buf.getvalue(), ".npz")

    run()


NPZ_TARGETS = ["rcsfaica", "rcsfaica_plain", "prototypes", "recording", "sfa", "sfa_quad",
               "ica", "reservoir"]


@pytest.mark.parametrize("name", NPZ_TARGETS)
def test_npz_field_mutations(files, name):
    _npz_field_test(files, name, QUICK)


def test_npz_field_mutation_is_refused_with_the_reason(files, tmp_path):
    """A few mutations the issue names, each refused with a message naming the array."""
    path = files["rcsfaica"][0]
    with np.load(path) as z:
        arrays = {k: z[k] for k in z.files}
    cases = {
        "output_std": (arrays["output_std"][:-1], "output_std must have shape"),
        "sfa_W": (np.where(np.arange(arrays["sfa_W"].size).reshape(arrays["sfa_W"].shape) == 5,
                           np.nan, arrays["sfa_W"]), "sfa_W contains 1 non-finite"),
        "ica_mean": (arrays["ica_mean"] + np.array([np.inf] + [0] * 3), "ica_mean contains"),
        "W_res": (arrays["W_res"] * 2, "spectral radius"),
        "leak": (arrays["leak"][::-1].copy(), "leak does not match"),
    }
    for key, (value, message) in cases.items():
        bad = dict(arrays, **{key: value})
        np.savez(tmp_path / f"{key}.npz", **bad)
        with pytest.raises(CorruptFileError, match=message):
            RCSFAICA.load(tmp_path / f"{key}.npz")


# --------------------------------------------------------------------- GraphML mutations
_NS = "{http://graphml.graphdrawing.org/xmlns}"


def _graphml_mutation():
    return st.tuples(
        st.sampled_from(["data", "remove_data", "remove_node", "remove_edge", "key_type",
                         "dup_node", "node_id", "add_edge"]),
        st.integers(0, 10_000),
        st.sampled_from(["-2", "-2.0", "nan", "NaN", "inf", "-inf", "1e400", "", "x", "3.5",
                         "-1", "0", "1", "2", "99999999999999999999", "true", "wait", "move",
                         "fly", "[]", "[[1, 2, 3]]", "[[0, null, 1.0, 1]]", "[[0, 1, 2, 0]]",
                         "[[-1, 0, 0, 1]]", "{}", "[[0, NaN, 0, 1]]", "4->5", "0->1"]),
    )


def _mutate_graphml(text: str, m) -> bytes:
    how, idx, value = m
    root = ET.fromstring(text)
    graph = root.find(f"{_NS}graph")
    nodes = graph.findall(f"{_NS}node")
    edges = graph.findall(f"{_NS}edge")
    datas = [d for el in [graph, *nodes] for d in el.findall(f"{_NS}data")]
    keys = root.findall(f"{_NS}key")
    if how == "data" and datas:
        datas[idx % len(datas)].text = value
    elif how == "remove_data" and datas:
        el = datas[idx % len(datas)]
        for parent in [graph, *nodes]:
            if el in list(parent):
                parent.remove(el)
    elif how == "remove_node" and nodes:
        graph.remove(nodes[idx % len(nodes)])
    elif how == "remove_edge" and edges:
        graph.remove(edges[idx % len(edges)])
    elif how == "key_type" and keys:
        keys[idx % len(keys)].set("attr.type", ["string", "int", "double", "boolean",
                                                 "long", "float"][idx % 6])
    elif how == "dup_node" and nodes:
        graph.append(nodes[idx % len(nodes)])
    elif how == "node_id" and nodes:
        nodes[idx % len(nodes)].set("id", value)
    elif how == "add_edge" and nodes:
        e = ET.SubElement(graph, f"{_NS}edge")
        e.set("source", nodes[idx % len(nodes)].get("id"))
        e.set("target", value)
    return ET.tostring(root)


def _graph_field_test(files, n: int) -> None:
    text = files["graph"][0].read_text()

    @settings(max_examples=n, deadline=None, derandomize=True, database=None,
              suppress_health_check=list(HealthCheck))
    @given(st.lists(_graphml_mutation(), min_size=1, max_size=3))
    def run(ms):
        t = text
        for m in ms:
            t = _mutate_graphml(t, m).decode()
        _try_load(files, "graph", t.encode(), ".graphml")

    run()


def test_graphml_field_mutations(files):
    _graph_field_test(files, 4 * QUICK)


@pytest.mark.parametrize("value", ["-2.0", "NaN", "inf", "-0.5"])
def test_graphml_bad_delay_is_refused(files, tmp_path, value):
    text = files["graph"][0].read_text()
    root = ET.fromstring(text)
    delay_key = next(k.get("id") for k in root.findall(f"{_NS}key")
                     if k.get("attr.name") == "delay")
    data = next(d for d in root.iter(f"{_NS}data") if d.get("key") == delay_key)
    data.text = value
    (tmp_path / "g.graphml").write_bytes(ET.tostring(root))
    with pytest.raises(CorruptFileError, match="delay"):
        TransitionGraph.from_graphml(tmp_path / "g.graphml")


# ------------------------------------------------------------------------ JSON mutations
_JSON_VALUES = st.sampled_from([None, -1, -2.5, 0, 1, 2, 1.5, 1e309, float("nan"), "x", "", True,
                                False, [], {}, [1, 2], [[0, 1, 0.5]], [[0, -1, 0.5]],
                                [[0, 1, 2.0]], {"a": 1}, 10**30])


def _paths(obj, prefix=()):
    yield prefix
    if isinstance(obj, dict):
        for k, v in obj.items():
            yield from _paths(v, (*prefix, k))
    elif isinstance(obj, list):
        for i, v in enumerate(obj):
            yield from _paths(v, (*prefix, i))


def _mutate_json(data, path, how, value):
    """A copy of the JSON document ``data`` with the field at ``path`` set to ``value``,
    deleted, or duplicated (``how``); the empty path replaces the whole document."""
    obj = json.loads(json.dumps(data))
    if not path:
        return value
    parent = obj
    for k in path[:-1]:
        parent = parent[k]
    k = path[-1]
    if how == "set":
        parent[k] = value
    elif how == "delete":
        del parent[k]
    elif isinstance(parent, list):
        parent.append(parent[k])
    else:
        parent[f"{k}_copy"] = parent[k]
    return obj


def _json_field_test(files, n: int) -> None:
    data = json.loads(files["drives"][0].read_text())
    paths = list(_paths(data))

    @settings(max_examples=n, deadline=None, derandomize=True, database=None,
              suppress_health_check=list(HealthCheck))
    @given(st.integers(0, 10_000), st.sampled_from(["set", "delete", "dup"]), _JSON_VALUES)
    def run(i, how, value):
        obj = _mutate_json(data, paths[i % len(paths)], how, value)
        _try_load(files, "drives", json.dumps(obj).encode(), ".json")

    run()


def test_json_field_mutations(files):
    _json_field_test(files, 4 * QUICK)


# ----------------------------------------------------------------------- snapshot mutations
def _snapshot_field_test(tmp_root: Path, n: int) -> None:
    import hashlib

    from hippo.snapshot import load_snapshot, save_snapshot
    from hippo.timing import SpectralTiming, TransitionCells

    t = SpectralTiming()
    cells = TransitionCells(t)
    for k in range(30):
        cells.step(t.step(k // 10, 0.2), 0.2)
    src = save_snapshot(cells, tmp_root / "snap_src")
    data = json.loads((src / "state.json").read_text())
    paths = list(_paths(data))
    arrays = (src / "arrays.npz").read_bytes()

    @settings(max_examples=n, deadline=None, derandomize=True, database=None,
              suppress_health_check=list(HealthCheck))
    @given(st.integers(0, 10**6), st.sampled_from(["set", "delete", "dup"]), _JSON_VALUES)
    def run(i, how, value):
        obj = _mutate_json(data, paths[i % len(paths)], how, value)
        MUTATED["files"] += 1
        with tempfile.TemporaryDirectory() as tmp:
            d = Path(tmp)
            text = json.dumps(obj)
            (d / "state.json").write_text(text)
            (d / "arrays.npz").write_bytes(arrays)
            (d / "manifest.json").write_text(json.dumps({
                "format": "hippo.snapshot/1", "class": "hippo.timing.transitions:TransitionCells",
                "sha256": {"state.json": hashlib.sha256(text.encode()).hexdigest(),
                           "arrays.npz": hashlib.sha256(arrays).hexdigest()}}))
            try:
                load_snapshot(d)
            except CorruptFileError:
                pass

    run()


def test_snapshot_field_mutations(tmp_path):
    """Damaged snapshots whose checksums were recomputed (so the decoder sees the damage):
    each loads or raises CorruptFileError; nothing else escapes."""
    _snapshot_field_test(tmp_path, 4 * QUICK)


# --------------------------------------------------------------------------- the big run
@pytest.mark.slow
def test_fuzz_over_ten_thousand_files(files):
    """> 10,000 mutated files over every loader (SLOW per loader and kind)."""
    start = MUTATED["files"]
    for name in BYTE_TARGETS:
        _byte_test(files, name, SLOW)
    for name in NPZ_TARGETS:
        _npz_field_test(files, name, SLOW)
    _graph_field_test(files, 2 * SLOW)
    _json_field_test(files, 2 * SLOW)
    with tempfile.TemporaryDirectory() as tmp:
        _snapshot_field_test(Path(tmp), 2 * SLOW)
    done = MUTATED["files"] - start
    print(f"{done} mutated files loaded, no crash")
    assert done >= 10_000 or SLOW < 700


def test_zip_with_a_huge_member_header_is_refused(tmp_path):
    """An npz whose member claims an absurd shape fails as a corrupt file, not a MemoryError."""
    header = (b"\x93NUMPY\x01\x00" + b"v\x00"
              + b"{'descr': '<f8', 'fortran_order': False, 'shape': (10000000000000,), }"
              .ljust(118) + b"\n")
    p = tmp_path / "huge.npz"
    with zipfile.ZipFile(p, "w") as z:
        z.writestr("format.npy", header)
    with pytest.raises(CorruptFileError):
        RCSFAICA.load(p)
