"""The Python module against the CLI: same bytes, same errors, cancel, no leak, no GIL held."""
import json
import os
import signal
import subprocess
import tempfile
import threading

import numpy as np
import pytest

import snvr

CLI = os.environ.get("SNVR_CLI", "snvr-cl")


def sphere(spacing=0.03, dtype=np.float32):
    """Points on a sphere of radius 0.3 about (0.5, 0.5, 0.5), exact in float32."""
    n = int(np.pi * 0.3 / spacing)
    rows = []
    for i in range(n):
        th = np.pi * (i + 0.5) / n
        m = max(1, int(2 * n * np.sin(th)))
        ph = 2 * np.pi * np.arange(m) / m
        rows.append(np.stack([0.5 + 0.3 * np.sin(th) * np.cos(ph), 0.5 + 0.3 * np.sin(th) * np.sin(ph),
                              np.full(m, 0.5 + 0.3 * np.cos(th))], axis=1))
    return np.concatenate(rows).astype(np.float32).astype(dtype)


SMALL = dict(resolution=32, device="openmp")


def test_dtypes_and_layouts_give_one_mesh():
    base = sphere()
    first = snvr.shell(base, **SMALL)
    assert first.faces.shape[1] == 3 and first.vertices.shape[1] == 3
    for points in (base.astype(np.float64), np.asfortranarray(base.astype(np.float64)), base.tolist(),
                   base[::1].copy(order="F")):
        other = snvr.shell(points, **SMALL)
        assert np.array_equal(other.vertices, first.vertices)
        assert np.array_equal(other.faces, first.faces)


def test_the_same_bytes_as_the_cli(tmp_path):
    points = tmp_path / "points.ply"
    subprocess.run([CLI, "sample", "sphere", "-o", str(points), "--spacing", "0.02"], check=True, capture_output=True)
    cli_stl = tmp_path / "cli.stl"
    subprocess.run([CLI, "reconstruct", str(points), "-o", str(cli_stl), "--resolution", "48", "--device", "openmp",
                    "--quiet"], check=True)
    mine = tmp_path / "mine.stl"
    s = snvr.shell(snvr.read_points(str(points)), resolution=48, device="openmp", written_as=".stl")
    s.write(str(mine))
    assert mine.read_bytes() == cli_stl.read_bytes()
    report = s.report
    assert report["check"]["points_inside"] == len(snvr.read_points(str(points)))
    assert report["mesh"]["closed"] and report["mesh"]["manifold"] and report["mesh"]["oriented"]
    # One report, two views: the dict has the keys and the figures of snvr-cl's --report.
    cli_json = tmp_path / "cli.json"
    subprocess.run([CLI, "reconstruct", str(points), "-o", str(tmp_path / "again.stl"), "--resolution", "48",
                    "--device", "openmp", "--quiet", "--report", str(cli_json)], check=True)
    cli_report = json.loads(cli_json.read_text())
    assert report.keys() == cli_report.keys()
    for section in ("grid", "offset", "flow", "mesh", "check"):
        assert report[section].keys() == cli_report[section].keys()
    for key in ("grid", "offset", "sampling_gap", "mesh", "pieces_dropped", "point_clusters"):
        assert report[key] == cli_report[key]
    check = {k: v for k, v in cli_report["check"].items() if k != "seconds"}
    assert {k: v for k, v in report["check"].items() if k != "seconds"} == check
    for ext in (".ply", ".obj", ".3mf"):
        s.write(str(tmp_path / ("out" + ext)))
        assert (tmp_path / ("out" + ext)).stat().st_size > 0


def test_outliers_come_back_as_a_mask():
    points = np.concatenate([sphere(), np.array([[3.0, 3, 3], [-2, 0.5, 4]], np.float32)])
    s = snvr.shell(points, **SMALL)
    mask = s.outlier_mask
    assert mask.dtype == bool and mask.shape == (len(points),)
    assert mask[-2:].all() and not mask[:-2].any()
    assert np.allclose(s.outliers, points[-2:])
    kept = snvr.shell(points, keep_outliers=True, **SMALL)
    assert not kept.outlier_mask.any()


@pytest.mark.parametrize("points, words", [
    (np.array([[0, 0, 0], [1, np.nan, 1], [0, 1, 0], [1, 1, 1]], float), "point 1 has a non-finite coordinate"),
    (np.zeros((5, 2)), "(N, 3)"),
    (np.zeros((0, 3)), "empty"),
    ([["a", "b", "c"]], "(N, 3) array of numbers"),
])
def test_bad_points_clear_errors(points, words):
    with pytest.raises(ValueError, match=words.replace("(", r"\(").replace(")", r"\)")):
        snvr.shell(points, **SMALL)


def test_bad_options_and_files():
    with pytest.raises(ValueError, match=r"\(--resolution\)"):
        snvr.shell(sphere(), resolution=5)
    with pytest.raises(ValueError, match="origin"):
        snvr.shell(sphere(), origin="middle")
    with pytest.raises(OSError, match="missing.ply"):
        snvr.read_points("/nonexistent/missing.ply")
    with pytest.raises(ValueError, match="xyz"):
        with tempfile.NamedTemporaryFile(suffix=".xyz") as f:
            f.write(b"0 0 0\n1 abc 1\n")
            f.flush()
            snvr.read_points(f.name)


def test_progress_cancels_and_ctrl_c_interrupts():
    seen = []

    def stop_at_step_two(stage, step, steps):
        seen.append(stage)
        return not (stage == "step" and step == 2)

    with pytest.raises(snvr.Cancelled, match="after step 2"):
        snvr.shell(sphere(), progress=stop_at_step_two, **SMALL)
    assert seen[:2] == ["outliers", "domain"] and seen[-1] == "step"

    def ctrl_c(stage, step, steps):
        if stage == "init":
            os.kill(os.getpid(), signal.SIGINT)

    with pytest.raises(KeyboardInterrupt):
        snvr.shell(sphere(), progress=ctrl_c, **SMALL)
    # The module is still usable after both.
    assert len(snvr.shell(sphere(), **SMALL).faces) > 0


def test_the_gil_is_released_while_the_solver_runs():
    count = [0]
    running = threading.Event()

    def spin():
        running.set()
        while running.is_set():
            count[0] += 1

    t = threading.Thread(target=spin)
    t.start()
    running.wait()
    before = count[0]
    snvr.shell(sphere(0.01), resolution=96, device="openmp")
    during = count[0] - before
    running.clear()
    t.join()
    assert during > 10000


def rss_bytes():
    with open("/proc/self/statm") as f:
        return int(f.read().split()[1]) * os.sysconf("SC_PAGE_SIZE")


def test_no_leak_over_100_runs():
    points = sphere()
    for _ in range(10):
        snvr.shell(points, **SMALL)
    start = rss_bytes()
    for _ in range(100):
        s = snvr.shell(points, **SMALL)
        s.vertices, s.faces, s.report
    assert rss_bytes() - start < 16 << 20


def test_round_trips_where_the_libraries_are_installed():
    s = snvr.shell(sphere(), **SMALL)
    for name, method, count in (("open3d", "to_open3d", lambda m: len(m.triangles)),
                                ("trimesh", "to_trimesh", lambda m: len(m.faces)),
                                ("pyvista", "to_pyvista", lambda m: m.n_cells)):
        try:
            __import__(name)
        except ImportError:
            continue
        assert count(getattr(s, method)()) == len(s.faces)


def test_read_points_keeps_the_files_floats_and_far_scans_centre_as_the_cli(tmp_path):
    points = tmp_path / "points.ply"
    subprocess.run([CLI, "sample", "sphere", "-o", str(points), "--spacing", "0.05"], check=True, capture_output=True)
    near = snvr.read_points(str(points))
    assert near.dtype == np.float32 and not near.flags["OWNDATA"]  # the reader's buffer, not a copy
    # A survey scan's coordinates: float32 STL would move the shell, so it is centred by
    # default (as snvr-cl does), and the bytes are snvr-cl's.
    far = tmp_path / "far.xyz"
    np.savetxt(far, near.astype(np.float64) * 10 + [512345.25, 4234567.5, 120.125], fmt="%.6f")
    cli_stl = tmp_path / "cli.stl"
    subprocess.run([CLI, "reconstruct", str(far), "-o", str(cli_stl), "--resolution", "32", "--device", "openmp",
                    "--quiet"], check=True)
    s = snvr.shell(str(far), resolution=32, device="openmp")
    assert s.report["input"]["origin_shift_why"].endswith("(default)") and s.shift[1] != 0
    s.write(str(tmp_path / "mine.stl"))
    assert (tmp_path / "mine.stl").read_bytes() == cli_stl.read_bytes()
    with pytest.raises(OSError, match="float"):
        snvr.shell(str(far), resolution=32, device="openmp", origin="keep")
    assert snvr.read_points(str(far)).dtype == np.float64


def test_units_and_scale_as_the_cli(tmp_path):
    points = tmp_path / "points.ply"
    subprocess.run([CLI, "sample", "sphere", "-o", str(points), "--spacing", "0.03"], check=True, capture_output=True)
    cli_stl = tmp_path / "cli.stl"
    subprocess.run([CLI, "reconstruct", str(points), "-o", str(cli_stl), "--resolution", "32", "--device", "openmp",
                    "--units", "cm", "--scale", "2", "--offset", "0.05", "--quiet"], check=True)
    s = snvr.shell(str(points), resolution=32, device="openmp", units="cm", scale=2, offset=0.05)
    s.write(str(tmp_path / "mine.stl"))
    assert (tmp_path / "mine.stl").read_bytes() == cli_stl.read_bytes()
    # Lengths given in cm times 2 come back in millimetres: 20 times the points' units.
    assert s.report["input"]["to_millimetres"] == 20 and s.report["offset"]["length"] == pytest.approx(1.0)
    plain = snvr.shell(str(points), resolution=32, device="openmp", offset=0.05)
    assert np.ptp(s.vertices[:, 0]) == pytest.approx(20 * np.ptp(plain.vertices[:, 0]), rel=1e-3)
    with pytest.raises(ValueError, match="unit 'furlong'"):
        snvr.shell(str(points), resolution=32, device="openmp", units="furlong")
    with pytest.raises(ValueError, match="scale"):
        snvr.shell(str(points), resolution=32, device="openmp", scale=0)


def test_a_file_that_changes_while_read_raises_oserror(tmp_path, monkeypatch):
    points = tmp_path / "points.ply"
    subprocess.run([CLI, "sample", "sphere", "-o", str(points), "--spacing", "0.03"], check=True, capture_output=True)
    data = points.read_bytes()
    # The library's test hook cuts the file short at a chosen byte while it is read.
    for fault, words in ((f"shrink:{len(data) // 2}", "shrank"), ("grow:10", "grew"), ("eio:10", "Input/output")):
        points.write_bytes(data)
        monkeypatch.setenv("SNVR_TEST_READ_FAULT", fault)
        with pytest.raises(OSError, match=words):
            snvr.shell(str(points), resolution=16, device="openmp")
        points.write_bytes(data)
        with pytest.raises(OSError, match=words):
            snvr.read_points(str(points))
    monkeypatch.delenv("SNVR_TEST_READ_FAULT")
    points.write_bytes(data)
    assert len(snvr.read_points(str(points))) > 0


def test_a_random_samplings_holes_are_closed_unless_kept():
    # 1,500 points at random on a sphere: holes wider than the offset, closed by points at their centres.
    rng = np.random.default_rng(3)
    directions = rng.normal(size=(1500, 3))
    points = 0.5 + 0.35 * directions / np.linalg.norm(directions, axis=1, keepdims=True)
    closed = snvr.shell(points, resolution=96, device="openmp")
    holes = closed.report["sampling_holes"]
    assert holes["share"] >= 0.04 and holes["points_added"] > 0
    assert closed.report["check"]["genus"] == 0 and closed.report["check"]["solids"] == 1
    kept = snvr.shell(points, resolution=96, device="openmp", points_as_given=True)
    assert kept.report["sampling_holes"]["points_added"] == 0
    assert kept.report["check"]["genus"] > 0


def test_tiles_give_the_whole_runs_shell():
    points = sphere(0.01)
    whole = snvr.shell(points, resolution=64, device="openmp")
    tiled = snvr.shell(points, resolution=64, device="openmp", tile_cells=16)
    assert tiled.report["tiles"]["core_cells"] == 16 and tiled.report["tiles"]["count"] == 64
    assert tiled.faces.shape == whole.faces.shape
    voxel = whole.report["grid"]["voxel"]
    assert np.abs(tiled.vertices - whole.vertices).max() <= 0.01 * voxel
    with pytest.raises(ValueError, match=r"tile size \(--tile-cells\)"):
        snvr.shell(points, resolution=64, tile_cells=12)


def test_memory_budget():
    points = sphere(0.01)
    fits = snvr.shell(points, resolution=64, device="openmp", max_memory=2**30)
    memory = fits.report["memory"]
    assert memory["budget_given"] and memory["budget_bytes"] == 2**30
    assert memory["estimated"]["peak"] <= 2**30 and fits.report["tiles"]["core_cells"] == 0
    with pytest.raises(MemoryError, match=r"memory budget \(--max-memory\) is 64 MiB"):
        snvr.shell(points, resolution=1024, device="openmp", max_memory=64 * 2**20)


def test_points_beyond_the_budget_go_to_files(tmp_path):
    points = sphere(0.0004)  # about 1.77 M points: the cloud's arrays of 4 MiB and more go to files
    whole = snvr.shell(points, resolution=64, device="openmp")
    spilled = snvr.shell(points, resolution=64, device="openmp", max_memory=64 * 2**20, temp_dir=str(tmp_path))
    files = spilled.report["memory"]["spilled"]
    assert files["arrays"] > 0 and files["folder"] == str(tmp_path)
    assert whole.report["memory"]["spilled"]["arrays"] == 0
    assert np.array_equal(spilled.vertices, whole.vertices) and np.array_equal(spilled.faces, whole.faces)
    assert not os.listdir(tmp_path)
