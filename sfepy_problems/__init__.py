"""SfePy problem files of contact-ssn, and their export helper.

``pip install .`` installs this folder as the package ``sfepy_problems``,
so that a problem file anywhere can write the contact solver's ``.npz``
through the public helper :mod:`sfepy_problems.export`
(``docs/own-problem.md``). The problem files shipped here load the helper
(``_export.py``) by path instead: a checkout then runs its own helper,
whichever copy of the package is installed, or none.

Importing this package imports neither SfePy nor any problem file.
"""
