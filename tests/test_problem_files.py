"""sfepy_problems/README.md gives one export command per problem file and
mesh (Table 1 needs the three block meshes), the same as the files'
``Usage examples::``, naming files and meshes that exist.

The commands themselves are run by tests/test_export.py (the 118 block, as
``python FILE.py`` and as ``sfepy-run``), tests/test_hertz.py,
tests/test_cattaneo_mindlin.py and tests/test_examples.py.
"""

import ast
import re
import shlex

import pytest

from conftest import ROOT

PROBLEMS = ROOT / "sfepy_problems"


def readme_commands():
    """The export commands of the README's table, in order."""
    text = (PROBLEMS / "README.md").read_text()
    return re.findall(r"^\|[^|]*\|[^|]*\| `(python sfepy_problems/[^`]+)` \|$",
                      text, flags=re.M)


def usage_commands(filename):
    """The ``python sfepy_problems/...`` commands of a file's docstring
    ``Usage examples::`` block, backslash continuations joined."""
    doc = ast.get_docstring(ast.parse((PROBLEMS / filename).read_text()))
    block = doc.split("Usage examples::", 1)[1].split("\n\n", 2)[1]
    block = re.sub(r"\\\n\s*", "", block)
    return [line.split("#")[0].strip() for line in block.splitlines()
            if line.strip().startswith("python sfepy_problems/")]


def parse(command):
    """(problem file, mesh, output) of an export command."""
    argv = shlex.split(command)
    assert argv[0] == "python"
    if "-d" not in argv:  # the two-DOF bar: python FILE OUTPUT
        return argv[1], None, argv[2]
    define = dict(re.findall(r"(\w+)='([^']*)'", argv[argv.index("-d") + 1]))
    return argv[1], define["mesh"], define["output"]


def test_readme_has_one_command_per_file_and_mesh():
    parsed = [parse(c) for c in readme_commands()]
    assert [(f, m) for f, m, _ in parsed] == [
        ("sfepy_problems/block_obstacle.py", "meshes/block_118.mesh"),
        ("sfepy_problems/block_obstacle.py", "meshes/block_454.mesh"),
        ("sfepy_problems/block_obstacle.py", "meshes/block_1878.mesh"),
        ("sfepy_problems/hertz_cylinder.py", "meshes/hertz.mesh"),
        ("sfepy_problems/cattaneo_mindlin.py", "meshes/hertz.mesh"),
        ("sfepy_problems/two_dof_bar.py", None)]
    outputs = [o for _, _, o in parsed]
    assert len(set(outputs)) == len(outputs)  # no export overwrites another
    for filename, mesh, output in parsed:
        assert (ROOT / filename).is_file()
        assert mesh is None or (ROOT / mesh).is_file()
        assert output.startswith("output/") and output.endswith(".npz")


@pytest.mark.parametrize("filename", ["block_obstacle.py", "hertz_cylinder.py",
                                      "cattaneo_mindlin.py", "two_dof_bar.py"])
def test_docstring_usage_matches_readme(filename):
    ours = usage_commands(filename)
    assert ours, f"{filename} has no export command in Usage examples"
    readme = [c for c in readme_commands()
              if parse(c)[0] == f"sfepy_problems/{filename}"]
    assert ours == readme
