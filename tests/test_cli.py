"""The command line as a user calls it: in a subprocess, checking exit status, stderr and the files left behind."""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

import polars as pl
import pytest
from conftest import REPO

MCAP = REPO / "highway_merge.mcap"


def cli(*args: str | Path, cwd: Path | None = None) -> subprocess.CompletedProcess:
    cmd = [sys.executable, "-m", "omega_prime_visibility.cli", "run", *map(str, args)]
    return subprocess.run(cmd, capture_output=True, text=True, cwd=cwd)


def assert_error(out: subprocess.CompletedProcess, *fragments: str) -> None:
    """Exit status 2 and exactly one stderr line, ``error: ...``, containing every fragment."""
    assert out.returncode == 2, out.stderr
    lines = out.stderr.splitlines()
    assert len(lines) == 1 and lines[0].startswith("error: "), out.stderr
    for fragment in fragments:
        assert fragment in lines[0]


def files_under(folder: Path) -> set[Path]:
    return {p.relative_to(folder) for p in folder.rglob("*")}


def test_cli_prints_table() -> None:
    out = subprocess.run(
        [sys.executable, "-m", "omega_prime_visibility.cli", "run", str(MCAP), "--no-progress"],
        capture_output=True,
        text=True,
        check=True,
    )
    assert "visibility" in out.stdout and "occluder_idxs" in out.stdout
    # then the per-target summary (analysis/summary.py): no sensors, so no out-of-view share
    summary = out.stdout[out.stdout.rindex("mean_visibility") - 400 :]
    assert "hidden_share" in summary and "partly_hidden_share" in summary and "out_of_view_share" not in summary


def test_cli_reports_corrupt_file(tmp_path) -> None:
    bad = tmp_path / "broken.mcap"
    bad.write_bytes(b"not an mcap at all")
    out = cli(bad)
    assert_error(out, "broken.mcap")
    assert "Traceback" not in out.stderr


def test_cli_writes_parquet_with_engine_and_several_egos(tmp_path) -> None:
    out_path = tmp_path / "vis.parquet"
    out = cli(MCAP, "--ego", "0,1", "--engine", "sweep", "--no-progress", "-o", out_path)
    assert out.returncode == 0, out.stderr
    table = pl.read_parquet(out_path)
    assert table.columns[:3] == ["frame", "total_nanos", "idx_ego"]
    assert set(table["idx_ego"].unique()) == {0, 1}
    # a dataset of parts (one here), no temporary file left beside it
    assert files_under(tmp_path) == {Path("vis.parquet"), Path("vis.parquet/part-000000.parquet")}
    again = cli(MCAP, "--ego", "0", "--engine", "sweep", "--no-progress", "-o", out_path)  # replaces it
    assert again.returncode == 0, again.stderr
    assert "idx_ego" not in pl.read_parquet(out_path).columns
    assert files_under(tmp_path) == {Path("vis.parquet"), Path("vis.parquet/part-000000.parquet")}


def test_cli_writes_csv_with_joined_lists(tmp_path) -> None:
    out = cli(MCAP, "--ego", "0", "--no-progress", "-o", "vis.csv", cwd=tmp_path)
    assert out.returncode == 0, out.stderr
    assert "wrote 1206 rows to vis.csv" in out.stdout
    assert files_under(tmp_path) == {Path("vis.csv")}
    table = pl.read_csv(tmp_path / "vis.csv")
    assert table.height == 1206
    # list columns are joined by spaces; the truck (idx 1) hides the merging cars in some frames
    assert table["occluder_idxs"].cast(pl.String).str.contains(r"(^| )1( |$)").any()


def test_cli_rejects_unknown_engine() -> None:
    out = cli(MCAP, "--engine", "nope")
    assert_error(out, "unknown engine 'nope'")


@pytest.mark.parametrize(
    ("output", "problem"),
    [
        ("out/x.parquet", "the folder out does not exist"),
        ("out/x.csv", "the folder out does not exist"),
        ("notes.txt/x.parquet", "notes.txt is not a folder"),
        ("taken.parquet", "taken.parquet: it is a directory"),
        ("x.txt", "must end in .parquet or .csv"),
        ("single.parquet", "single.parquet: it is a single file, and the output is a folder of parquet parts"),
    ],
)
def test_cli_bad_output_path_fails_before_computing(tmp_path, output: str, problem: str) -> None:
    (tmp_path / "notes.txt").write_text("a file, not a folder")
    (tmp_path / "taken.parquet").mkdir()
    (tmp_path / "single.parquet").write_bytes(b"PAR1 a file written by someone else PAR1")
    before = files_under(tmp_path)
    out = cli(MCAP, "--ego", "0", "--no-progress", "-o", output, cwd=tmp_path)
    assert_error(out, f"cannot write {output}", problem)
    assert out.stdout == ""
    assert files_under(tmp_path) == before


def test_cli_unwritable_output_place() -> None:
    out = cli(MCAP, "--ego", "0", "--no-progress", "-o", "/proc/x.parquet")
    assert_error(out, "cannot write /proc/x.parquet", "cannot create files in /proc")
    assert not Path("/proc/x.parquet").exists()


@pytest.mark.skipif(os.name != "posix" or os.geteuid() == 0, reason="root may write into read-only folders")
def test_cli_read_only_folder(tmp_path) -> None:
    folder = tmp_path / "ro"
    folder.mkdir()
    folder.chmod(0o555)
    try:
        out = cli(MCAP, "--ego", "0", "--no-progress", "-o", folder / "x.csv")
        assert_error(out, f"cannot write {folder / 'x.csv'}", "cannot create files in")
        assert list(folder.iterdir()) == []
    finally:
        folder.chmod(0o755)


@pytest.mark.parametrize("ego", ["x", "ALL", "0,,1"])
def test_cli_bad_ego_is_one_line(ego: str) -> None:
    out = cli(MCAP, "--ego", ego, "--no-progress")
    assert_error(out, f"--ego takes an idx, a comma-separated list of idx, or 'all', not {ego!r}")
    assert ("lower case" in out.stderr) == (ego == "ALL")


def test_cli_unknown_ego_lists_idx() -> None:
    out = cli(MCAP, "--ego", "99", "--no-progress")
    assert_error(out, "ego idx [99] never occurs", "idx present: [0, 1, 2, 3, 4, 5, 6]")


def test_cli_osi_without_host_vehicle_lists_idx(shared_data) -> None:
    out = cli(shared_data / "pedestrian.osi", "--map", shared_data / "fabriksgatan.xodr", "--no-progress")
    # which idx is the vehicle and which the pedestrian: the types tell
    assert_error(out, "pedestrian.osi names no host vehicle", "pass --ego IDX", "VEHICLE idx [0]; PEDESTRIAN idx [1]")


def test_cli_osi_with_map_and_ego_runs(shared_data, tmp_path) -> None:
    out = cli(shared_data / "pedestrian.osi", "--map", shared_data / "fabriksgatan.xodr", "--ego", "0", "--no-progress")
    assert out.returncode == 0, out.stderr
    assert "visibility" in out.stdout


def test_cli_missing_map(tmp_path) -> None:
    out = cli(MCAP, "--map", tmp_path / "nowhere.xodr", "--no-progress")
    assert_error(out, f"map {tmp_path / 'nowhere.xodr'} does not exist")


@pytest.mark.parametrize(
    ("name", "content", "problem"),
    [
        ("notes.txt", "just some text\n", "no map reader for '.txt' files"),
        ("notes.xodr", "just some text\n", "as OpenDRIVE (XML error"),
        ("other.xodr", "<html><body/></html>\n", "its XML root is <html>, not <OpenDRIVE>"),
    ],
)
def test_cli_map_that_is_no_map(tmp_path, name: str, content: str, problem: str) -> None:
    (tmp_path / name).write_text(content)
    out = cli(MCAP, "--map", tmp_path / name, "--no-progress")
    assert_error(out, f"cannot read map {tmp_path / name}", problem)
    assert out.stdout == ""


def test_cli_osi_trace_with_text_map(shared_data, tmp_path) -> None:
    (tmp_path / "map.txt").write_text("not a map")
    out = cli(shared_data / "pedestrian.osi", "--map", tmp_path / "map.txt", "--ego", "0", "--no-progress")
    assert_error(out, f"cannot read map {tmp_path / 'map.txt'}")


def test_cli_sensors_layout_and_file(tmp_path) -> None:
    out_path = tmp_path / "s.parquet"
    out = cli(MCAP, "--ego", "0", "--engine", "sweep", "--sensors", "typical", "--no-progress", "-o", out_path)
    assert out.returncode == 0, out.stderr
    table = pl.read_parquet(out_path)
    assert table.columns[3:5] == ["sensor", "occluder_idxs"] and table.columns[-2:] == ["in_view", "status"]
    assert table["sensor"].n_unique() == 6
    sensors = tmp_path / "one.json"
    sensors.write_text('[{"name": "front", "fov": 1.0, "range": 50}]')
    printed = cli(MCAP, "--ego", "0", "--engine", "sweep", "--sensors", sensors, "--no-progress")
    assert printed.returncode == 0, printed.stderr
    assert "front" in printed.stdout and "status" in printed.stdout


def test_cli_bad_sensors(tmp_path) -> None:
    assert_error(cli(MCAP, "--sensors", "lidar"), "unknown sensor layout 'lidar'")
    bad = tmp_path / "bad.json"
    bad.write_text('[{"name": "a", "fov": 9}]')
    assert_error(cli(MCAP, "--sensors", bad), "bad.json", "fov must be in")
    bad.write_text("{")
    assert_error(cli(MCAP, "--sensors", bad), "not valid JSON")


def test_cli_static_occluders_from_geojson(tmp_path) -> None:
    import shapely

    from omega_prime_visibility import get_visibility_df
    from omega_prime_visibility.inputs.io import read_recording

    wall = shapely.LineString([(60, -5.4), (140, -5.4)])
    (tmp_path / "wall.geojson").write_text(shapely.to_geojson(wall))
    out = cli(MCAP, "--ego", "0", "--static", tmp_path / "wall.geojson", "--no-progress", "-o", tmp_path / "v.parquet")
    assert out.returncode == 0, out.stderr
    expected = get_visibility_df(read_recording(MCAP), 0, [wall], progress=False)
    assert expected["static_occluder_idxs"].list.len().sum() > 0
    assert pl.read_parquet(tmp_path / "v.parquet").equals(expected)


def test_cli_bad_static_file(tmp_path) -> None:
    (tmp_path / "walls.wkt").write_text("LINESTRING (0 0, 1 1)\nnot wkt\n")
    assert_error(cli(MCAP, "--static", tmp_path / "walls.wkt"), "walls.wkt, line 2, as WKT")
    assert_error(
        cli(MCAP, "--static", tmp_path / "none.wkt"), f"static occluders {tmp_path / 'none.wkt'} does not exist"
    )


def test_version_on_the_command_line_and_in_the_package() -> None:
    from importlib.metadata import version

    import omega_prime_visibility

    installed = version("omega-prime-visibility")
    assert omega_prime_visibility.__version__ == installed
    out = subprocess.run(
        [sys.executable, "-m", "omega_prime_visibility.cli", "--version"], capture_output=True, text=True
    )
    assert out.returncode == 0, out.stderr
    assert out.stdout.strip() == f"omega-prime-visibility {installed}" and out.stderr == ""


@pytest.mark.parametrize("command", [[], ["run"], ["batch"], ["animate"], ["report"], ["engines"]])
def test_help_reads_as_prose(command: list[str]) -> None:
    """No type tags, no raw double backticks, and nothing cut off (a [trace, map] in the text included)."""
    out = subprocess.run(
        [sys.executable, "-m", "omega_prime_visibility.cli", *command, "--help"],
        capture_output=True,
        text=True,
        env={**os.environ, "COLUMNS": "80"},
    )
    assert out.returncode == 0, out.stderr
    text = out.stdout
    for tag in ("<bool>", "<str>", "<path>", "<int>", "<float>", "<list", "``"):
        assert tag not in text, tag
    assert not any(line.rstrip().endswith("...") for line in text.splitlines()[1:]), text
    flat = " ".join(text.split())
    if command == ["batch"]:
        assert "or a JSON list of [trace, map] pairs" in flat
    if command == ["run"]:
        assert "a .csv path becomes one file with the list columns" in flat
        assert "batch writes one .parquet file per recording" in flat


def cli_command(*args: str | Path, cwd: Path | None = None) -> subprocess.CompletedProcess:
    """Any command (``cli`` is ``run``'s)."""
    cmd = [sys.executable, "-m", "omega_prime_visibility.cli", *map(str, args)]
    return subprocess.run(cmd, capture_output=True, text=True, cwd=cwd)


def test_cli_truncated_mcap_says_so(tmp_path) -> None:
    cut = tmp_path / "cut.mcap"
    cut.write_bytes(MCAP.read_bytes()[:500_000])
    out = cli(cut, "--no-progress")
    assert_error(out, f"cannot read {cut}: the file is truncated")
    assert "RecordLengthLimitExceeded" not in out.stderr


def test_cli_sensor_yaw_in_degrees(tmp_path) -> None:
    sensors = tmp_path / "deg.json"
    sensors.write_text('[{"name": "left", "yaw": 90, "fov": 1.0}]')
    assert_error(cli(MCAP, "--sensors", sensors), "deg.json", "yaw 90 looks like degrees; sensor angles are radians")


def test_cli_animate_unknown_target(tmp_path) -> None:
    out = cli_command("animate", MCAP, "-o", tmp_path / "a.gif", "--target", "99", "--no-progress")
    assert_error(out, "target idx 99 never occurs in the recording", "idx present: [0, 1, 2, 3, 4, 5, 6]")
    assert not (tmp_path / "a.gif").exists()


def test_cli_engine_of_the_other_mode_names_the_flag() -> None:
    out = cli(MCAP, "--engine", "raycast3d", "--no-progress")
    assert_error(out, "unknown engine 'raycast3d'", "pass --mode 3d")
    assert "mode='3d'" not in out.stderr


def test_cli_3d_warning_is_one_readable_line(tmp_path, widths_as_heights_mcap) -> None:
    out = cli(widths_as_heights_mcap, "--mode", "3d", "--ego", "0", "--no-progress", "-o", tmp_path / "v.csv")
    assert out.returncode == 0, out.stderr
    warned = [line for line in out.stderr.splitlines() if line.startswith("warning: ")]
    assert len(warned) == 1 and "the heights look like a copy of the widths" in warned[0]
    # no Python warning format (file:line: Category: ...) and no source line under it
    assert "VisibilityInputWarning" not in out.stderr and "get_visibility_df(" not in out.stderr
    assert all(line.startswith(("warning: ", "omega-prime-visibility: ")) for line in out.stderr.splitlines())


def test_cli_run_takes_the_batch_map_list(shared_data) -> None:
    out = cli(shared_data / "pedestrian.osi", "--map", shared_data / "mapping.json", "--ego", "0", "--no-progress")
    assert out.returncode == 0, out.stderr
    assert "visibility" in out.stdout


def test_cli_run_map_list_without_the_trace(shared_data, tmp_path) -> None:
    (tmp_path / "maps.json").write_text(f'[["other.osi", "{shared_data / "fabriksgatan.xodr"}"]]')
    out = cli(shared_data / "pedestrian.osi", "--map", tmp_path / "maps.json", "--ego", "0", "--no-progress")
    assert_error(out, f"the map list {tmp_path / 'maps.json'} has no map for pedestrian.osi")


def test_cli_osi_trace_without_map_is_read_without_one(shared_data) -> None:
    """Documented: an OSI trace without --map is read without a map (the visibility needs none)."""
    out = cli(shared_data / "pedestrian.osi", "--ego", "0", "--no-progress")
    assert out.returncode == 0, out.stderr
    assert "visibility" in out.stdout
    help_text = " ".join(cli("--help").stdout.split())
    assert "An OSI trace without --map is read without a map" in help_text


def test_cli_choices_give_the_api_table(tmp_path) -> None:
    from omega_prime_visibility import get_visibility_df
    from omega_prime_visibility.inputs.io import read_recording

    path = tmp_path / "v.parquet"
    out = cli(MCAP, "--ego", "0", "--occluders", "CAR", "--targets", "3,2", "--measure", "area", "-o", path)
    assert out.returncode == 0, out.stderr
    expected = get_visibility_df(read_recording(MCAP), 0, occluders=["CAR"], targets=[2, 3], measure="area")
    assert pl.read_parquet(path).equals(expected)


@pytest.mark.parametrize(
    ("args", "fragments"),
    [
        (["--occluders", "lorries"], ["--occluders: unknown object kind 'lorries'", "vehicles", "or idx"]),
        (["--targets", "1,CAR"], ["--targets takes comma-separated names", "'1,CAR'"]),
        (["--targets", "99"], ["--targets: idx [99] never occur"]),
        (["--measure", "area", "--mode", "3d"], ["--measure area measures footprints in 2D", "--mode 2d"]),
        (["--measure", "volume"], ["unknown measure 'volume'"]),
        (["--measure", "area", "--engine", "sweep"], ["--measure area has its own exact engine", "leave --engine"]),
    ],
)
def test_cli_bad_choices_are_one_line(args: list[str], fragments: list[str]) -> None:
    result = cli(MCAP, "--no-progress", *args)
    assert_error(result, *fragments)
    assert "polars" not in result.stderr  # a shell user cannot give an expression


@pytest.mark.parametrize(
    ("content", "name", "fragments"),
    [
        (b"", "empty.mcap", ["the file is empty"]),
        (b"", "empty.osi", ["the file is empty"]),
        (b"hello", "notes.txt", ["omega-prime reads MCAP files (.mcap), OSI traces (.osi)", "not '.txt' files"]),
        (b"some text", "text.mcap", ["it is not an MCAP file"]),
        (b"x", "noext", ["not files without an extension"]),
    ],
)
def test_cli_unreadable_recordings_say_why(tmp_path, content: bytes, name: str, fragments: list[str]) -> None:
    (tmp_path / name).write_bytes(content)
    out = cli(tmp_path / name, "--ego", "0", "--no-progress")
    assert_error(out, str(tmp_path / name), *fragments)
    assert "Error:" not in out.stderr and "NotImplementedError" not in out.stderr
    (tmp_path / "folder.mcap").mkdir()
    assert_error(cli(tmp_path / "folder.mcap", "--no-progress"), "is a folder, not a recording file")


@pytest.mark.parametrize(
    ("args", "fragments"),
    [
        (["--workers", "0"], ["--workers takes a number of processes, at least 1, not 0"]),
        (["--workers", "-2"], ["--workers takes a number of processes, at least 1, not -2"]),
        (["--rows", "-5"], ["--rows takes a number of rows to print, 0 or more, not -5"]),
        (["--map-occluders"], ["--map-occluders needs a recording that carries an OpenDRIVE map", "--map FILE.xodr"]),
    ],
)
def test_cli_bad_numbers_and_map_occluders_are_one_line(args: list[str], fragments: list[str]) -> None:
    assert_error(cli(MCAP, "--ego", "0", "--no-progress", *args), *fragments)


def test_cli_bad_map_lists_say_what_is_expected(tmp_path, shared_data) -> None:
    for text in ('{"a": 1}', '[["a.osi"]]', "nope"):
        (tmp_path / "maps.json").write_text(text)
        out = cli(shared_data / "acc-test.osi", "--map", tmp_path / "maps.json", "--no-progress")
        assert_error(out, "cannot read the map list", "expected a JSON list of [trace, map] pairs")


def test_compile_refuses_jobs_below_one() -> None:
    for jobs in ("0", "-3"):
        assert_error(
            cli_command("compile", "--jobs", jobs), f"--jobs takes a number of processes, at least 1, not {jobs}"
        )


def test_engines_lists_the_defaults() -> None:
    out = cli_command("engines")
    assert out.returncode == 0, out.stderr
    lines = out.stdout.splitlines()
    assert "visilibity (--mode 2d, the default)" in lines and "silhouette3d (--mode 3d, the default)" in lines
    assert "raycast3d (--mode 3d, the default with static meshes)" in lines and lines[-1].startswith("area")


def test_help_reads_as_a_shell_user_expects() -> None:
    # usage lines name arguments as click does (RECORDING, INPUTS...), never in braces; the main help names every
    # command; no jargon in the options
    from omega_prime_visibility.cli.app import ORDER

    main = subprocess.run(
        [sys.executable, "-m", "omega_prime_visibility.cli", "--help"], capture_output=True, text=True
    )
    words = " ".join(main.stdout.split())
    assert all(f"'{name}" in words for name in ORDER), words
    for command, usage in (("run", "[OPTIONS] RECORDING"), ("batch", "[OPTIONS] INPUTS..."), ("report", "RECORDING")):
        out = subprocess.run([sys.executable, "-m", "omega_prime_visibility.cli", command, "--help"],
                             capture_output=True, text=True)  # fmt: skip
        first = out.stdout.splitlines()[0]
        assert usage in first and "{" not in first, first
        assert "sampled" not in out.stdout


@pytest.mark.parametrize("output", ["print", "parquet"])
def test_a_run_imports_nothing_it_does_not_need(output: str, tmp_path) -> None:
    # issue 41: the plotting package (its animation module pulled in matplotlib's friends: 0.17 s) and
    # pyarrow.compute (polars converting a pyarrow list column: 0.13 s) are not needed to print a table; nor is
    # pandas to write one (pyarrow's pa.array of a numpy array imported it: 0.25 s)
    where = "'--rows', '0'" if output == "print" else f"'-o', {str(tmp_path / 'out.parquet')!r}"
    code = (
        "import sys; from omega_prime_visibility.cli import main; "
        f"sys.argv = ['omega-prime-visibility', 'run', 'highway_merge.mcap', '--engine', 'sweep', {where}, "
        "'--no-progress']\n"
        "status = 0\ntry:\n    main()\nexcept SystemExit as stop:\n    status = stop.code or 0\n"
        "loaded = ('omega_prime', 'matplotlib', 'pyarrow.compute', 'omega_prime_visibility.plot.animate', 'pandas')\n"
        "print('exit', status, 'imported:', sorted(m for m in loaded if m in sys.modules))"
    )
    done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, cwd=REPO, timeout=600)
    assert done.stdout.strip().splitlines()[-1] == "exit 0 imported: []", done.stderr
    if output == "parquet":  # the run did its work
        assert pl.read_parquet(tmp_path / "out.parquet").height == 1206  # every row of the printed table


@pytest.mark.parametrize(
    "command", [["--help"], ["to-parquet", "--help"], ["from-osi", "--help"], ["visualize", "--help"]]
)
def test_omega_primes_own_command_line_runs_in_our_environment(command) -> None:
    # omega-prime 0.3.7's CLI passes Option(click_type=...), which typer 0.29 refused at import: we pin typer below it
    script = Path(sys.executable).parent / "omega-prime"
    run = subprocess.run([str(script), *command], capture_output=True, text=True)
    assert run.returncode == 0, run.stderr[-1000:]
    assert "Usage" in run.stdout


def test_rows_bounds_the_per_target_summary_too() -> None:
    out = subprocess.run([sys.executable, "-m", "omega_prime_visibility", "run", str(REPO / "highway_merge.mcap"),
                          "--ego", "0", "--rows", "2", "--no-progress"], capture_output=True, text=True)  # fmt: skip
    assert out.returncode == 0, out.stderr
    summary = out.stdout.split("per target")[1]
    assert "and 4 more targets (--rows N shows N of them)" in summary
    shown = [line.split("┆")[0].strip("│ ") for line in summary.splitlines() if line.startswith("│ ") and "┆" in line]
    assert shown[-2:] == ["1", "2"]  # idx 1 and 2 of the six targets (after the header lines)
    mcap = str(REPO / "highway_merge.mcap")
    everything = subprocess.run([sys.executable, "-m", "omega_prime_visibility", "run", mcap, "--ego", "0",
                                 "--no-progress"], capture_output=True, text=True)  # fmt: skip
    assert "more targets" not in everything.stdout


def test_ctrl_c_in_run_says_so_and_exits_130(monkeypatch, tmp_path) -> None:
    from typer.testing import CliRunner

    import omega_prime_visibility.api as api
    from omega_prime_visibility.cli import app

    def interrupted(*args, **kwargs):
        raise KeyboardInterrupt

    monkeypatch.setattr(api, "get_visibility_df", interrupted)
    out = tmp_path / "vis.parquet"
    result = CliRunner().invoke(app, ["run", str(REPO / "highway_merge.mcap"), "--ego", "0", "-o", str(out)])
    assert result.exit_code == 130
    assert f"interrupted; nothing was written to {out}" in result.output
    assert not out.exists()
