"""Every file the shell blocks of the README or of a page in docs/ write
lies where .gitignore covers it (issue 34, part of point 24), so that pasting the
commands leaves ``git status`` clean.

The paths are read from the commands (``-o``, ``--output``, ``--outdir``,
``output='...'`` in ``-d``, the folder beside ``python -m solver FILE``,
``two_dof_bar.py FILE``, ``mkdir``, ``cp``'s target, ``python -m venv``
and, after ``cd``, the working folder itself) and asked of git
(``git check-ignore --no-index``). A command the parser does not know
fails the test, so that a new kind of command gets a rule here.
"""

import re
import shlex
import shutil
import subprocess
from pathlib import PurePosixPath

import pytest

from conftest import ROOT

DOCUMENTS = ["README.md"] + sorted(
    str(p.relative_to(ROOT)) for p in (ROOT / "docs").glob("*.md"))
#: Commands that write nothing outside ignored folders (pip: build/,
#: *.egg-info; pytest: .pytest_cache/) or only install or read.
QUIET = {"pip", "apt-get", ".", "source", "jupyter"}


def document_blocks(name):
    """A document's bash blocks, joined in order: pasted one after the
    other, they run in one shell (a ``cd`` in one holds for the next)."""
    text = (ROOT / name).read_text()
    return "\n".join(re.findall(r"```bash\n(.*?)```", text, flags=re.S))


def commands(block):
    """Each command of a block as argv: continuation lines joined,
    comments dropped, split at && and ;, environment assignments and an
    mpiexec prefix removed."""
    for line in block.replace("\\\n", " ").splitlines():
        argv, part = shlex.split(line, comments=True), []
        for token in argv + ["&&"]:
            if token not in ("&&", ";"):
                part.append(token)
                continue
            while part and re.fullmatch(r"[A-Z_]+=.*", part[0]):
                part = part[1:]
            if part[:1] == ["mpiexec"]:
                part = part[part.index("python"):]
            if part:
                yield part
            part = []


def option(argv, *names):
    for i, token in enumerate(argv[:-1]):
        if token in names:
            return argv[i + 1]
    return None


def written(block):
    """The paths (relative to the repository root; folders end in /) that
    the block's commands write."""
    cwd, paths = PurePosixPath("."), []
    for argv in commands(block):
        program = argv[0]
        if program in QUIET:
            continue
        if program == "cd":
            cwd = cwd / argv[1]
        elif program == "mkdir":
            paths += [f"{cwd / p}/" for p in argv[1:] if not p.startswith("-")]
        elif program == "cp":
            paths.append(f"{cwd / argv[-1]}/" if argv[-1].endswith("/")
                         else str(cwd / argv[-1]))
        elif program in ("python", "python3", "sfepy-run"):
            if argv[1:3] == ["-m", "pytest"]:
                continue
            if argv[1:3] == ["-m", "venv"]:
                paths.append(f"{cwd / argv[-1]}/")
                continue
            if argv[1:4] == ["-m", "solver", "convert"]:  # X.npz → DIR
                paths.append(f"{cwd / argv[5]}/")
                continue
            if cwd != PurePosixPath("."):
                paths.append(f"{cwd}/")  # a script's default output
            out = option(argv, "-o", "--output", "--outdir")
            if out is not None:
                paths.append(str(cwd / out))
            define = option(argv, "-d")
            if define and "output=" in define:
                paths.append(str(cwd / re.search(r"output='([^']+)'",
                                                 define)[1]))
            if argv[1:3] == ["-m", "solver"] and out is None:
                paths.append(f"{(cwd / argv[3]).parent}/")
            if argv[1].endswith("two_dof_bar.py"):
                paths.append(str(cwd / argv[2]))
        else:
            raise AssertionError(f"no rule for the command {argv}")
    return paths


GIT = shutil.which("git") is not None and subprocess.run(
    ["git", "-C", str(ROOT), "rev-parse"], capture_output=True).returncode == 0
needs_git = pytest.mark.skipif(not GIT, reason="needs git and a checkout")


def unignored(paths):
    """The paths that .gitignore does not cover."""
    check = subprocess.run(["git", "check-ignore", "--no-index", "--stdin",
                            "-n", "-v"], cwd=ROOT, input="\n".join(paths),
                           capture_output=True, text=True)
    return [line.split("\t")[1] for line in check.stdout.splitlines()
            if line.startswith("::")]


def test_rules_find_the_outputs():
    """The parser sees the outputs of the kinds of commands the documents
    use, and a path outside output/ is reported (the README's mesh command
    before it wrote into output/)."""
    block = ("mkdir -p output/x\ncd output/x\npython a.py\n"
             "python -m solver y.npz\n"
             "python meshes/generate.py --size 0.1 -o fine.mesh  # c\n")
    assert set(written(block)) == {"output/x/", "output/x/fine.mesh"}
    assert written('sfepy-run f.py -d "mesh=\'m\', output=\'o/p.npz\'" && '
                   "python -m solver o/p.npz --plots") == ["o/p.npz", "o/"]
    root = "python meshes/generate.py --size 0.1 -o fine.mesh"
    assert written(root) == ["fine.mesh"]
    if GIT:
        assert unignored(["fine.mesh", "output/fine.mesh", ".venv/"]) == [
            "fine.mesh"]


@needs_git
@pytest.mark.parametrize("name", DOCUMENTS)
def test_blocks_write_only_ignored_paths(name):
    paths = written(document_blocks(name))
    assert not paths or not unignored(paths), unignored(paths)
