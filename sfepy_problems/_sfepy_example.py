r"""The common part of ``sfepy_contact_sphere.py`` and
``sfepy_contact_planes.py``: what SfePy's two contact examples share (the
cube ``cube_medium_hexa.mesh``, the material, the fixed bottom, the Newton
settings) and their problem description, for the export to the contact
solver (SfePy solves nothing, ``_export.NO_SOLVE``) or for SfePy's own
penalty solve of the example (``penalty=k``). A helper loaded by path, as
``_export.py``; not a problem file."""
import importlib.util
import os.path as op
import sys

from sfepy import data_dir
from sfepy.mechanics.matcoefs import stiffness_from_lame

#: The examples' mesh, in SfePy's data folder.
MESH = op.join(data_dir, 'meshes', '3d', 'cube_medium_hexa.mesh')
#: The examples' Lamé parameters (E = 10, ν = 0.3).
LAM, MU = 5.769, 3.846
#: The examples' penalty k and Newton settings.
K_PENALTY = 1e5
NEWTON = {'i_max': 50, 'eps_a': 1e-14, 'eps_r': 1e-8, 'eps_mode': 'or',
          'step_red': 0.8, 'ls_on': 2.0, 'check': 0, 'delta': 1e-6}
#: The penalty terms' quadrature on the faces of the top: SfePy's examples
#: (Gauss, order 6 per direction), or at the faces' vertices (the
#: trapezoidal rule on the reference square [0, 1]²: the penalty at the
#: nodes, lumped, as the contact solver's constraints).
QUADRATURES = {'gauss': 6,
               'nodes': (1, [[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]],
                         [0.25, 0.25, 0.25, 0.25])}


def load_export():
    """``sfepy_problems/_export.py`` by path (this folder is not a package)."""
    name = '_contact_ssn_sfepy_export'
    if name not in sys.modules:
        spec = importlib.util.spec_from_file_location(
            name, op.join(op.dirname(op.abspath(__file__)), '_export.py'))
        module = importlib.util.module_from_spec(spec)
        sys.modules[name] = module
        spec.loader.exec_module(module)
    return sys.modules[name]


def young_poisson(lam, mu):
    """(E, ν) of the Lamé parameters λ, μ."""
    return mu * (3 * lam + 2 * mu) / (lam + mu), lam / (2 * (lam + mu))


def export(pb, variables, obstacle, meta):
    """The body of a ``post_process_hook_final``: write the ``.npz`` of the
    contact solver (K, f = 0, M, ``obstacle``; ``meta`` plus E, ν, λ, μ),
    or with ``penalty`` SfePy's own displacement
    (:func:`_export.save_displacement`)."""
    conf = pb.conf.options
    if conf.penalty is not None:
        return load_export().save_displacement(pb, variables, conf.export)
    E, nu = young_poisson(LAM, MU)
    return load_export().export_contact_problem(
        pb, variables, conf.export,
        stiffness='dw_lin_elastic.i.Omega(solid.D, v, u)', load=None,
        obstacle=obstacle,
        meta=dict(meta, E=E, nu=nu, lam=LAM, mu=MU,
                  mesh=op.basename(pb.conf.filename_mesh),
                  supports='bottom z = -0.5 fixed',
                  contact_boundary='top z = 0.5'))


def problem(hook, mesh, output, penalty, i_max, quadrature, verbose,
            contact_materials, contact_terms):
    """The problem description (what ``define()`` returns) of one example:
    ``hook`` its ``post_process_hook_final``, ``contact_materials`` and
    ``contact_terms`` (with the integral ``ic`` on the region ``Top``) its
    penalty terms, used with ``penalty`` only; the other arguments those of
    ``define()``."""
    load_export().set_verbosity(verbose)  # before SfePy's 'left over:'
    if quadrature not in QUADRATURES:
        raise ValueError(f'quadrature must be one of {sorted(QUADRATURES)}, '
                         f'got {quadrature!r}')
    filename_mesh = op.abspath(mesh)
    options = {
        'output_dir': op.dirname(op.abspath(output)),
        'output_format': 'vtk',
        'save_results': False,
        'post_process_hook_final': hook,
        'nls': 'newton',
        'ls': 'ls',
        'export': op.abspath(output),
        'penalty': penalty,
    }
    regions = {
        'Omega': 'all',
        'Bottom': ('vertices in (z < -0.499)', 'facet'),
        'Top': ('vertices in (z > 0.499)', 'facet'),
        'Gamma_c': ('copy r.Top', 'facet'),
    }
    materials = dict(contact_materials, solid=(
        {'D': stiffness_from_lame(dim=3, lam=LAM, mu=MU)},))
    fields = {
        'displacement': ('real', 'vector', 'Omega', 1),
        'scalar': ('real', 'scalar', 'Omega', 1),
    }
    variables = {
        'u': ('unknown field', 'displacement', 0),
        'v': ('test field', 'displacement', 'u'),
        # Only for assembling M in the export hook:
        'p': ('unknown field', 'scalar', 1),
        'q': ('test field', 'scalar', 'p'),
    }
    ebcs = {
        'fixed': ('Bottom', {'u.all': 0.0}),
    }
    integrals = {'i': 2, 'ic': QUADRATURES[quadrature]}
    if penalty is None:
        equations = {
            'balance_of_forces': 'dw_lin_elastic.i.Omega(solid.D, v, u) = 0',
        }
        newton = dict(load_export().NO_SOLVE)
    else:  # SfePy's example: the penalty terms on the top
        equations = {
            'elasticity': 'dw_lin_elastic.2.Omega(solid.D, v, u)'
            + ''.join(f' + {term}' for term in contact_terms) + ' = 0',
        }
        newton = dict(NEWTON, i_max=i_max)
    solvers = {
        'ls': ('ls.scipy_direct', {}),
        'newton': ('nls.newton', newton),
    }
    return {key: value for key, value in locals().items()
            if key in ('filename_mesh', 'options', 'regions', 'materials',
                       'fields', 'variables', 'ebcs', 'integrals',
                       'equations', 'solvers')}
