"""Fault tests: the real command in a subprocess, and what a failed write leaves behind.

Each case starts from a good earlier result in the output folder and checks
that after the fault the old file is byte-for-byte intact and nothing else
(no temporary or partial file) is in the folder.
"""

import os
import resource
import shutil
import signal
import subprocess
import sys

import pytest

PAUSE_ENV = "CRUSTVIEW_TEST_PAUSE_BEFORE_RENAME"  # crustview.atomic.PAUSE_ENV, spelled out for runs on old code

ENV = {k: v for k, v in os.environ.items() if k != PAUSE_ENV}


def _cmd(*args):
    return [sys.executable, "-m", "crustview", *map(str, args)]


@pytest.fixture(scope="module")
def sample(tmp_path_factory):
    from crustview.core.samples.manifolds import get_manifold
    from crustview.io import write_points

    folder = tmp_path_factory.mktemp("sample")
    write_points(folder / "torus.npy", get_manifold("torus").sample(1500, seed=0).points)
    write_points(folder / "other.npy", get_manifold("torus").sample(1200, seed=1).points)
    return folder


@pytest.fixture(scope="module")
def victims(tmp_path_factory, sample):
    """For each suffix, a good earlier result (of another sample), made once by the real command."""
    folder = tmp_path_factory.mktemp("victims")
    for outputs in (("-o", folder / "victim.npz", "--report", folder / "victim.json"), ("-o", folder / "victim.ply")):
        subprocess.run(
            _cmd("reconstruct", sample / "other.npy", "-d", 2, *outputs), env=ENV, check=True, capture_output=True
        )
    return folder


@pytest.fixture
def setup(tmp_path, sample, victims):
    """An input and, for each suffix, a good earlier result (of another sample) to be overwritten.

    Each test gets its own copies of the module's results (made once: the
    faults are in the commands the tests run, not in these).
    """
    shutil.copy(sample / "torus.npy", tmp_path / "torus.npy")
    old = {}
    for suffix in (".npz", ".ply", ".json"):
        victim = tmp_path / f"victim{suffix}"
        shutil.copyfile(victims / victim.name, victim)
        old[victim.name] = victim.read_bytes()
    return tmp_path, old


def _listing(folder):
    return sorted(p.name for p in folder.iterdir())


def _intact(folder, old):
    for name, data in old.items():
        assert (folder / name).read_bytes() == data, f"{name} changed"
    assert _listing(folder) == sorted([*old, "torus.npy"]), "a temporary or partial file was left"


def _fsize_limit(limit):
    def apply():
        resource.setrlimit(resource.RLIMIT_FSIZE, (limit, limit))

    return apply


def _limited(limit, source, *outputs):
    """The real command reconstructing ``source`` under a file-size limit of ``limit`` bytes."""
    return subprocess.run(
        _cmd("reconstruct", source, "-d", 2, *outputs),
        env=ENV,
        capture_output=True,
        text=True,
        preexec_fn=_fsize_limit(limit),
        timeout=120,
    )


@pytest.mark.parametrize("name", ["victim.npz", "victim.ply"])
def test_a_file_size_limit_below_the_result_keeps_the_old_result(setup, name):
    folder, old = setup
    limit = len(old[name]) // 3  # the new result (of a larger sample) is bigger still
    run = _limited(limit, folder / "torus.npy", "-o", folder / name)
    assert run.returncode == 2, run.stderr
    lines = run.stderr.strip().splitlines()
    assert len(lines) == 1 and "Cannot write" in lines[0] and "File too large" in lines[0], run.stderr
    _intact(folder, old)


def test_a_file_size_limit_on_the_report_keeps_the_old_report(setup):
    folder, old = setup
    out = folder / "new.npz"
    run = subprocess.run(
        _cmd("reconstruct", folder / "torus.npy", "-d", 2, "-o", out, "--report", folder / "victim.json"),
        env=ENV,
        capture_output=True,
        text=True,
        preexec_fn=_fsize_limit(600),  # the result fails first; nothing may be left
        timeout=120,
    )
    assert run.returncode == 2, run.stderr
    _intact(folder, old)


def test_kill_9_between_writing_and_renaming_keeps_the_old_result(setup):
    folder, old = setup
    target = folder / "victim.npz"
    proc = subprocess.Popen(
        _cmd("reconstruct", folder / "torus.npy", "-d", 2, "-o", target),
        env={**ENV, PAUSE_ENV: "60"},
        stderr=subprocess.PIPE,
        stdout=subprocess.DEVNULL,
        text=True,
    )
    try:
        seen = ""
        for line in proc.stderr:  # until the hook says the data is written (or the command ends)
            seen += line
            if "pausing before renaming" in line:
                break
        # today's code writes in place: by now the old result is gone; the new code has it all in an unnamed file
        proc.send_signal(signal.SIGKILL)
        proc.wait(timeout=30)
    finally:
        if proc.poll() is None:
            proc.kill()
        proc.stderr.close()
    _intact(folder, old)
    assert "pausing before renaming" in seen, seen


def _terminal_ctrl_c() -> None:
    """In the child: Ctrl-C as a shell on a terminal leaves it (default), whatever the test worker inherited.

    A child inherits an ignored SIGINT, and Python then keeps ignoring it; the
    pytest-xdist worker that runs these tests may have it ignored (in one of
    two full runs the command slept through the signal).
    """
    signal.signal(signal.SIGINT, signal.SIG_DFL)


def _communicate_or_kill(proc: subprocess.Popen, group: bool = False) -> tuple[str, str]:
    """The child's output once it ends; a child still running after 30 s is killed (with its group)
    and the test fails, so that no process outlives it into the next tests."""
    try:
        return proc.communicate(timeout=30)
    except subprocess.TimeoutExpired:
        if group:
            os.killpg(proc.pid, signal.SIGKILL)
        else:
            proc.kill()
        proc.communicate()
        raise


def test_ctrl_c_cancels_cleanly_with_one_line_and_no_partial_file(setup):
    folder, old = setup
    proc = subprocess.Popen(
        _cmd("reconstruct", folder / "torus.npy", "-d", 2, "-o", folder / "victim.ply"),
        env={**ENV, PAUSE_ENV: "60"},
        stderr=subprocess.PIPE,
        stdout=subprocess.PIPE,
        text=True,
        preexec_fn=_terminal_ctrl_c,
    )
    for line in proc.stderr:
        if "pausing before renaming" in line:
            break
    proc.send_signal(signal.SIGINT)
    out, err = _communicate_or_kill(proc)
    assert proc.returncode == 130
    assert err.strip().splitlines() == ["crustview: cancelled (Ctrl-C); no partial file was written"]
    assert out == ""
    _intact(folder, old)


def _make_read_only(folder):
    """A folder in which no file can be created, though its files stay writable (root ignores modes: chattr +i)."""
    if os.geteuid() != 0:
        folder.chmod(0o555)
        return lambda: folder.chmod(0o755)
    run = subprocess.run(["chattr", "+i", str(folder)], capture_output=True)
    if run.returncode != 0:
        pytest.skip(f"cannot make a read-only folder as root here: {run.stderr.decode().strip()}")
    return lambda: subprocess.run(["chattr", "-i", str(folder)], check=True)


def _reconstruct_in(closed, folder, *outputs):
    """The real command on ``folder``'s torus with ``outputs``, while ``closed`` is a read-only folder."""
    undo = _make_read_only(closed)
    try:
        return subprocess.run(
            _cmd("reconstruct", folder / "torus.npy", "-d", 2, *outputs),
            env=ENV,
            capture_output=True,
            text=True,
            timeout=120,
        )
    finally:
        undo()


def test_a_read_only_folder_keeps_the_old_result(setup):
    folder, old = setup
    run = _reconstruct_in(folder, folder, "-o", folder / "victim.npz")
    assert run.returncode == 2, run.stderr
    lines = run.stderr.strip().splitlines()
    assert len(lines) == 1 and "Cannot write" in lines[0], run.stderr
    _intact(folder, old)


def test_a_read_only_report_folder_fails_before_the_run_and_writes_nothing(setup, tmp_path_factory):
    """The result's folder is writable, the report's is not: the command stops before reconstructing."""
    folder, old = setup
    closed = tmp_path_factory.mktemp("closed")
    run = _reconstruct_in(closed, folder, "-o", folder / "new.npz", "--report", closed / "r.json")
    assert run.returncode == 2, run.stderr
    lines = run.stderr.strip().splitlines()
    assert len(lines) == 1 and f"the folder '{closed}' cannot be written to (creating a file there: " in lines[0]
    _intact(folder, old)  # no new.npz
    assert _listing(closed) == []


def test_a_result_that_cannot_be_written_puts_the_previous_report_back(setup):
    """A file-size limit that the new report fits under and the result does not: the report is written
    first, the result fails, and the previous report is back byte for byte (a failed command writes nothing)."""
    folder, old = setup
    limit = 2 * len(old["victim.json"])
    assert len(old["victim.npz"]) > 2 * limit  # the premise: the result (of a larger sample) cannot fit
    run = _limited(limit, folder / "torus.npy", "-o", folder / "victim.npz", "--report", folder / "victim.json")
    assert run.returncode == 2, run.stderr
    assert "victim.npz" in run.stderr and "File too large" in run.stderr, run.stderr
    _intact(folder, old)


def test_a_missing_folder_writes_nothing_at_all(setup):
    folder, old = setup
    run = subprocess.run(
        _cmd(
            "reconstruct", folder / "torus.npy", "-d", 2, "-o", folder / "new.npz", "--report", folder / "no" / "r.json"
        ),
        env=ENV,
        capture_output=True,
        text=True,
        timeout=120,
    )
    assert run.returncode == 2
    assert (
        run.stderr.strip()
        == f"crustview: error: Cannot write '{folder / 'no' / 'r.json'}': the folder '{folder / 'no'}' does not exist."
    )
    _intact(folder, old)  # in particular no new.npz: the run did not start


def test_an_output_named_like_the_input_is_refused_without_force(setup):
    folder, old = setup
    src = folder / "torus.npy"
    before = src.read_bytes()
    for out in (src, folder / "." / "torus.npy"):
        run = subprocess.run(_cmd("reconstruct", src, "-d", 2, "-o", out), env=ENV, capture_output=True, text=True)
        assert run.returncode == 2
        assert "Refusing to write over the input file" in run.stderr and "--force" in run.stderr
        assert src.read_bytes() == before
    _intact(folder, old)
    ply = folder / "victim.ply"  # a result read back as input, written over only with --force
    inode = ply.stat().st_ino
    run = subprocess.run(_cmd("reconstruct", ply, "-d", 2, "-o", ply), env=ENV, capture_output=True, text=True)
    assert run.returncode == 2 and ply.read_bytes() == old["victim.ply"] and ply.stat().st_ino == inode
    run = subprocess.run(
        _cmd("reconstruct", ply, "-d", 2, "-o", ply, "--force"), env=ENV, capture_output=True, text=True
    )
    assert run.returncode == 0, run.stderr
    assert ply.stat().st_ino != inode  # written anew (the same bytes: the run is deterministic)
    assert _listing(folder) == sorted([*old, "torus.npy"])


def test_a_stale_named_temporary_of_a_killed_process_is_swept(tmp_path):
    from crustview.atomic import TEMP_SUFFIX, write_bytes

    target = tmp_path / "out.json"
    dead = subprocess.Popen([sys.executable, "-c", "pass"])
    dead.wait()
    stale = tmp_path / f".out.json.{dead.pid}.abcd{TEMP_SUFFIX}"
    stale.write_bytes(b"half")
    mine = tmp_path / f".out.json.{os.getpid()}.abcd{TEMP_SUFFIX}"
    mine.write_bytes(b"in progress")  # a live process's: kept
    write_bytes(target, b"{}")
    assert target.read_bytes() == b"{}" and not stale.exists() and mine.exists()


def test_ctrl_c_stops_a_batch_and_its_workers_with_one_line(setup, sample):
    folder, old = setup
    out = folder / "out"
    proc = subprocess.Popen(
        _cmd("reconstruct", sample / "torus.npy", sample / "other.npy", "-d", 2, "--out-dir", out, "-j", 2),
        env={**ENV, PAUSE_ENV: "60"},
        stderr=subprocess.PIPE,
        stdout=subprocess.PIPE,
        text=True,
        start_new_session=True,  # a process group of its own, as a terminal's foreground job
        preexec_fn=_terminal_ctrl_c,
    )
    for line in proc.stderr:  # a worker has its result written, not yet renamed
        if "pausing before renaming" in line:
            break
    os.killpg(proc.pid, signal.SIGINT)  # Ctrl-C reaches the whole group
    out_text, err = _communicate_or_kill(proc, group=True)
    assert proc.returncode == 130
    assert err.strip().splitlines()[-1] == "crustview: cancelled (Ctrl-C); no partial file was written"
    assert "Traceback" not in err and out_text == ""
    assert list(out.iterdir()) == []
    assert _listing(folder) == sorted([*old, "torus.npy", "out"])
