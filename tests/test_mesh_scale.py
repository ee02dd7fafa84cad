"""The mesh scripts at any size (issue 34, point 12).

``python meshes/hertz.py --radius 10`` used to stop ("radius too large for
generate.clean_mesh's snapping": the block's absolute edge snapping), and a
small radius got the R = 1 element sizes, i.e. a handful of elements. Every
length and tolerance of the scripts is now relative to the geometry, so a
mesh of radius R is the R = 1 mesh scaled. The reference is that R = 1
mesh, the committed ``meshes/hertz.mesh`` (51 arc nodes within the Hertz
half-width 0.1 R of the default load, ``meshes/README.md``), and, for the
contact boundary, the problem file's own region Γc (the arc below
y = -0.8 R) as SfePy selects it.
"""


import meshio
import numpy as np
import pytest
from scipy.spatial import cKDTree

from conftest import MESHES, ROOT, load_script
from test_export import export_module

RADII = (10.0, 0.01)


def _load(name, filename):
    return load_script(name, MESHES / filename)


generate = _load("_contact_ssn_meshes_generate", "generate.py")
hertz = _load("_contact_ssn_meshes_hertz", "hertz.py")
sphere = _load("_contact_ssn_meshes_hertz_sphere", "hertz_sphere.py")
two_body = _load("_contact_ssn_meshes_two_body", "two_body.py")


def contact_arc(points, R):
    """Nodes on the arc below y = -0.8 R (Γc of hertz_cylinder.py)."""
    on = hertz.arc_nodes(points, R)
    return on[points[on, 1] < -0.8 * R + 1e-9 * R]


@pytest.fixture(scope="module")
def reference():
    points = meshio.read(MESHES / "hertz.mesh").points[:, :2]
    return points, contact_arc(points, 1.0)


@pytest.mark.parametrize("R", RADII)
def test_hertz_half_disc_at_any_radius(R, reference, tmp_path):
    """A valid mesh: no duplicate nodes, all triangles positive, the area of
    the half-disc, the flat side and the symmetry axis exact, as many nodes
    in the contact zone as at R = 1; and hertz_cylinder.py finds Γc on it:
    its contact nodes are the arc's nodes below y = -0.8 R."""
    points, triangles = hertz.hertz_mesh(radius=R)
    distance, _ = cKDTree(points).query(points, k=2)
    assert distance[:, 1].min() > 1e-4 * R  # h_contact = 0.004 R
    areas = generate.signed_areas(points, triangles)
    assert areas.min() > 0
    # the half-disc's area, less the chords' segments (h_far = 0.1 R)
    assert areas.sum() == pytest.approx(np.pi * R ** 2 / 2, rel=3e-3)
    assert points[:, 1].max() == 0.0 and points[:, 0].min() == -R
    np.testing.assert_array_equal(np.unique(triangles),
                                  np.arange(len(points)))
    arc = contact_arc(points, R)
    ref_points, ref_arc = reference
    assert abs(len(arc) - len(ref_arc)) <= 2
    zone = np.abs(points[hertz.arc_nodes(points, R), 0]) < 0.1 * R
    ref_zone = np.abs(ref_points[hertz.arc_nodes(ref_points, 1.0), 0]) < 0.1
    assert abs(zone.sum() - ref_zone.sum()) <= 2

    mesh = tmp_path / "hertz.mesh"
    hertz.write_mesh(mesh, points, triangles)
    from solver import load_problem

    out = tmp_path / "hertz.npz"
    export_module().export_only(ROOT / "sfepy_problems" / "hertz_cylinder.py",
                                mesh=str(mesh), output=str(out), R=R,
                                d=0.016 * R)
    problem = load_problem(out)
    assert sorted(problem.contact_nodes) == sorted(arc)


def test_hertz_command_with_radius_10(tmp_path, capsys):
    """The command of the issue, into a folder that does not exist yet."""
    out = tmp_path / "new" / "hertz_R10.mesh"
    assert hertz.main(["--radius", "10", "-o", str(out)]) == 0
    assert capsys.readouterr().out.startswith(f"{out}: ")
    points = meshio.read(out).points
    assert np.hypot(points[:, 0], points[:, 1]).max() == pytest.approx(10.0)


def test_block_snapping_is_relative_to_the_block():
    """clean_mesh snaps within SNAP_TOL times the box's size: 1e-9 for the
    10 x 20 block (as before), 1e-6 for a box a thousand times larger, and
    not at all without a box."""
    for scale in (1.0, 1e3):
        off = 0.5e-9 * scale  # within the tolerance
        far = 5e-9 * scale    # beyond it
        points = np.array([[5 * scale - off, 0.0], [0.0, 10 * scale + off],
                           [5 * scale - far, 1.0]])
        box = (5 * scale, 10 * scale)
        cleaned, _ = generate.clean_mesh(points, [[0, 1, 2]], box=box)
        assert cleaned[0, 0] == 5 * scale and cleaned[1, 1] == 10 * scale
        assert cleaned[2, 0] == 5 * scale - far
    kept, _ = generate.clean_mesh(points, [[0, 1, 2]], box=None)
    np.testing.assert_array_equal(kept, points)


def test_sphere_snapping_is_relative_to_the_radius():
    R = 1e4
    points = np.array([[1e-13 * R, 1.0, 2.0], [3.0, -1e-13 * R, 2.0],
                       [3.0, 1.0, R * (1 - 1e-13)], [1e-9 * R, 1.0, 2.0]])
    snapped = sphere.snap(points, ((0, 0.0), (1, 0.0), (2, R)), R)
    assert snapped[0, 0] == 0.0 and snapped[1, 1] == 0.0
    assert snapped[2, 2] == R
    assert snapped[3, 0] == 1e-9 * R  # beyond 1e-12 R: left alone


@pytest.mark.parametrize("R", RADII)
def test_quarter_sphere_at_any_radius(R):
    """Positive tetrahedra, no duplicate nodes, nodes exactly on the
    symmetry planes and the flat top, the contact point a node."""
    points, tets = sphere.hertz_sphere_mesh(2, radius=R)
    e = points[tets[:, 1:]] - points[tets[:, :1]]
    volume = np.einsum("ij,ij->i", e[:, 0], np.cross(e[:, 1], e[:, 2])) / 6
    assert volume.min() > 0
    assert volume.sum() == pytest.approx(np.pi * R ** 3 / 6, rel=0.02)
    distance, _ = cKDTree(points).query(points, k=2)
    assert distance[:, 1].min() > 1e-4 * R
    assert points[:, :2].min() == 0.0 and points[:, 2].max() == R
    assert (np.abs(points) < 1e-12 * R).all(axis=1).sum() == 1
    radius = np.linalg.norm(points - [0, 0, R], axis=1)
    low = (np.abs(radius - R) < 1e-6 * R) & (points[:, 2] < 0.2 * R)
    assert low.sum() > 20  # the contact surface, below z = 0.2 R


def test_two_cylinders_at_radius_10():
    """two_body.py cylinders --r1 10 --r2 15 (it used hertz.py's mesh)."""
    points, triangles, group = two_body.cylinders_mesh(10.0, 15.0)
    areas = generate.signed_areas(points, triangles)
    assert areas.min() > 0
    for body, R in ((2, 10.0), (1, 15.0)):
        assert areas[group == body].sum() == pytest.approx(
            np.pi * R ** 2 / 2, rel=3e-3)  # chords of 0.1 R


@pytest.mark.parametrize("script, argv, message", [
    ("hertz_sphere.py", ["--a-over-h", "0", "-o", "x.mesh"],
     "argument --a-over-h: must be a positive number, got 0"),
    ("hertz_sphere.py", ["--a-over-h", "2", "--a", "3", "-o", "x.mesh"],
     "a (3) must be less than the radius (1)"),
    ("block3d.py", ["--layers", "0", "-o", "x.mesh"],
     "need layers >= 1 and a positive thickness, got 0 and 10.0"),
])
def test_bad_arguments_are_one_line(script, argv, message, tmp_path, capsys,
                                    monkeypatch):
    monkeypatch.chdir(tmp_path)
    module = {"hertz_sphere.py": sphere,
              "block3d.py": _load("_contact_ssn_meshes_block3d",
                                  "block3d.py")}[script]
    try:
        code = module.main(argv)
    except SystemExit as exc:
        code = exc.code
    assert code in (1, 2)
    assert capsys.readouterr().err == f"{script}: error: {message}\n"
    assert not (tmp_path / "x.mesh").exists()
