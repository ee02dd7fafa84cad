r"""The safe expression parser behind the obstacle curves and surfaces.
Expressions travel as text inside the ``.npz`` problem file and are parsed
**without** :func:`eval`: :func:`ast.parse`, every node checked against a
whitelist (numbers, the variables, ``pi``, ``e``, ``+ - * / **``, unary
signs, a fixed set of elementary functions) and translated into SymPy for
exact derivatives, evaluated by :func:`sympy.lambdify`. Sizes, nesting
depths and constants are bounded (the ``MAX_*`` limits), so a hostile
file cannot exhaust memory or time here."""

import ast
import math

import numpy as np
import sympy

from ..errors import ExpressionError

__all__ = ["ALLOWED_FUNCTIONS", "ALLOWED_CONSTANTS", "MAX_LENGTH",
           "MAX_DEPTH", "MAX_CALL_DEPTH", "MAX_DERIVATIVE_NODES",
           "parse_expression"]
class RealSign(sympy.Function):
    """sign(x) of a real argument, derivative 0 (almost everywhere: the
    curve is evaluated in floating point, where the kink is not hit)."""

    @classmethod
    def eval(cls, arg):
        if arg.is_Number:
            return sympy.sign(arg)
        if arg.is_extended_positive:
            return sympy.Integer(1)
        if arg.is_extended_negative:
            return sympy.Integer(-1)
        return None

    def fdiff(self, argindex=1):
        return sympy.Integer(0)

    def _eval_evalf(self, prec):
        return sympy.sign(self.args[0])._eval_evalf(prec)

    def _numpycode(self, printer):
        return f"numpy.sign({printer._print(self.args[0])})"

    _lambdacode = _numpycode


class RealAbs(sympy.Function):
    """|x| of a real argument: derivative sign(x)·x'. (SymPy's Abs cannot
    tell that an argument such as sqrt(t) is real for every t of interest
    and differentiates through real and imaginary parts, which grows fast
    with nesting.)"""

    @classmethod
    def eval(cls, arg):
        if arg.is_Number:
            return abs(arg)
        if arg.is_extended_nonnegative:
            return arg
        if arg.is_extended_nonpositive:
            return -arg
        return None

    def fdiff(self, argindex=1):
        return RealSign(self.args[0])

    def _eval_evalf(self, prec):
        return sympy.Abs(self.args[0])._eval_evalf(prec)

    def _numpycode(self, printer):
        return f"numpy.abs({printer._print(self.args[0])})"

    _lambdacode = _numpycode

    def _sympystr(self, printer):
        return f"abs({printer._print(self.args[0])})"


#: Functions an obstacle expression may call, by name (NumPy-style aliases
#: included so that expressions copied from NumPy code keep working).
ALLOWED_FUNCTIONS = {
    "sin": sympy.sin, "cos": sympy.cos, "tan": sympy.tan,
    "asin": sympy.asin, "acos": sympy.acos, "atan": sympy.atan,
    "arcsin": sympy.asin, "arccos": sympy.acos, "arctan": sympy.atan,
    "sinh": sympy.sinh, "cosh": sympy.cosh, "tanh": sympy.tanh,
    "exp": sympy.exp, "log": sympy.log, "sqrt": sympy.sqrt, "abs": RealAbs,
}

#: Named constants an obstacle expression may use.
ALLOWED_CONSTANTS = {"pi": sympy.pi, "e": sympy.E}

_BINARY = {
    ast.Add: lambda a, b: a + b,
    ast.Sub: lambda a, b: a - b,
    ast.Mult: lambda a, b: a * b,
    ast.Div: lambda a, b: a / b,
    ast.Pow: None,  # handled separately, see _power
}
_UNARY = {ast.UAdd: lambda a: a, ast.USub: lambda a: -a}
_HINTS = {ast.BitXor: " (use ** for powers)"}

#: Longest expression text accepted (a guard against pathological input).
MAX_LENGTH = 1000

#: Deepest nesting of the parsed SymPy expression tree (SymPy flattens
#: long sums and products): exact derivatives of deep compositions grow
#: quadratically (first) and cubically (second) with the depth.
MAX_DEPTH = 30

#: Most function calls nested in one another, sin(cos(exp(t))) = 3: SymPy's
#: assumption queries cost exponentially in this depth for some mixtures.
MAX_CALL_DEPTH = 8

#: Largest first derivative accepted, in expression-tree nodes (a product
#: of k factors has a derivative of k products): beyond it the obstacle is
#: refused as too complex rather than differentiated for minutes.
MAX_DERIVATIVE_NODES = 5000


def _power(base, exponent):
    # Exact (or arbitrary-precision) powers of constants such as 9**9**9**9
    # would take forever in SymPy; compute them in double precision instead,
    # where they overflow at once.
    if base.is_Number and exponent.is_Number:
        try:
            return sympy.Float(math.pow(float(base), float(exponent)))
        except (OverflowError, ValueError, ZeroDivisionError):
            raise ExpressionError(
                f"constant power {float(base):g}**{float(exponent):g} is not "
                "a finite real number") from None
    return base ** exponent


def _translate(node, symbols, text):
    """Translate one whitelisted AST node into a SymPy expression
    (``symbols``: the variables by name)."""
    if isinstance(node, ast.Expression):
        return _translate(node.body, symbols, text)
    if isinstance(node, ast.Constant):
        value = node.value
        if isinstance(value, bool) or not isinstance(value, (int, float)):
            raise ExpressionError(
                f"{text!r}: constant {value!r} is not a real number")
        return sympy.Integer(value) if isinstance(value, int) \
            else sympy.Float(value)
    if isinstance(node, ast.Name):
        if node.id in symbols:
            return symbols[node.id]
        if node.id in ALLOWED_CONSTANTS:
            return ALLOWED_CONSTANTS[node.id]
        raise ExpressionError(
            f"{text!r}: unknown name {node.id!r} (allowed: "
            f"{', '.join(map(repr, symbols))}, "
            f"{', '.join(sorted(ALLOWED_CONSTANTS))})")
    if isinstance(node, ast.BinOp):
        op = type(node.op)
        if op not in _BINARY:
            raise ExpressionError(
                f"{text!r}: operator {op.__name__} is not allowed"
                + _HINTS.get(op, ""))
        left = _translate(node.left, symbols, text)
        right = _translate(node.right, symbols, text)
        if op is ast.Pow:
            return _power(left, right)
        return _BINARY[op](left, right)
    if isinstance(node, ast.UnaryOp):
        op = type(node.op)
        if op not in _UNARY:
            raise ExpressionError(
                f"{text!r}: unary operator {op.__name__} is not allowed")
        return _UNARY[op](_translate(node.operand, symbols, text))
    if isinstance(node, ast.Call):
        if not isinstance(node.func, ast.Name) \
                or node.func.id not in ALLOWED_FUNCTIONS:
            name = node.func.id if isinstance(node.func, ast.Name) \
                else ast.unparse(node.func)
            raise ExpressionError(
                f"{text!r}: call of {name!r} is not allowed (allowed "
                f"functions: {', '.join(sorted(ALLOWED_FUNCTIONS))})")
        if node.keywords or len(node.args) != 1 \
                or isinstance(node.args[0], ast.Starred):
            raise ExpressionError(
                f"{text!r}: {node.func.id}() takes exactly one positional "
                "argument")
        argument = _translate(node.args[0], symbols, text)
        return ALLOWED_FUNCTIONS[node.func.id](argument)
    raise ExpressionError(
        f"{text!r}: {type(node).__name__} is not allowed in an obstacle "
        f"expression (only numbers, {', '.join(symbols)}, pi, e, "
        "+ - * / **, and elementary functions)")


def parse_expression(text, variable="t"):
    """Parse an arithmetic expression in one variable into SymPy, safely.

    ``text`` is in Python syntax, e.g. ``"5.05 + 0.005*t**2"``; ``variable``
    the name of the curve parameter, or several (a surface's ``("s", "t")``
    or ``("x", "y")``), each ``sympy.Symbol(name, real=True)``. Returns a
    real expression whose free symbols are among them. ExpressionError if the
    text is not a string, is empty or too long, does not parse, uses anything
    outside the whitelist (module docstring), nests too deeply
    (:data:`MAX_CALL_DEPTH`, :data:`MAX_DEPTH`), or has a constant part that
    is not a finite real double (``1/0``, ``sqrt(-1)``, ``exp(1000)``)."""
    if not isinstance(text, str):
        raise ExpressionError(
            f"expression must be a string, not {type(text).__name__}")
    if not text.strip():
        raise ExpressionError("expression is empty")
    if len(text) > MAX_LENGTH:
        raise ExpressionError(
            f"expression is longer than {MAX_LENGTH} characters")
    try:
        tree = ast.parse(text.strip(), mode="eval")
    except SyntaxError as exc:
        raise ExpressionError(
            f"{text!r}: syntax error ({exc.msg})") from None
    calls = _call_depth(tree)
    if calls > MAX_CALL_DEPTH:
        raise ExpressionError(f"{text!r}: too many nested function calls "
                              f"({calls} > {MAX_CALL_DEPTH})")
    names = (variable,) if isinstance(variable, str) else tuple(variable)
    symbols = {name: sympy.Symbol(name, real=True) for name in names}
    symbol = symbols[names[0]]
    try:
        expr = _translate(tree, symbols, text)
    except ExpressionError as exc:
        if str(exc).startswith(repr(text)):
            raise
        raise ExpressionError(f"{text!r}: {exc}") from None
    except RecursionError:
        raise ExpressionError(f"{text!r}: expression nests too deeply") \
            from None
    except (OverflowError, ValueError, TypeError, ZeroDivisionError) as exc:
        raise ExpressionError(f"{text!r}: cannot be evaluated ({exc})") \
            from None
    depth = _depth(expr)
    if depth > MAX_DEPTH:
        raise ExpressionError(f"{text!r}: expression nests too deeply "
                              f"(depth {depth} > {MAX_DEPTH})")
    if expr.has(sympy.zoo, sympy.oo, -sympy.oo, sympy.nan):
        raise ExpressionError(f"{text!r}: is not finite (division by zero?)")
    if expr.has(sympy.I):
        raise ExpressionError(f"{text!r}: is not real")
    check_constants(expr, text, symbol)
    if expr.is_Number and not math.isfinite(float(expr)):
        raise ExpressionError(f"{text!r}: is not finite")
    return expr


def _call_depth(tree):
    """Deepest nesting of calls in a Python AST (iterative: no recursion)."""
    deepest, stack = 0, [(tree, 0)]
    while stack:
        node, level = stack.pop()
        if isinstance(node, ast.Call):
            level += 1
            deepest = max(deepest, level)
        stack.extend((child, level) for child in ast.iter_child_nodes(node))
    return deepest


def _depth(expr):
    """Depth of a SymPy expression tree (an atom has depth 1)."""
    deepest, stack = 0, [(expr, 1)]
    while stack:
        node, level = stack.pop()
        deepest = max(deepest, level)
        stack.extend((arg, level + 1) for arg in node.args)
    return deepest


def expression_size(expr, limit):
    """Number of nodes of a SymPy expression tree, counted up to ``limit``."""
    count = 0
    for _ in sympy.preorder_traversal(expr):
        count += 1
        if count > limit:
            break
    return count


def check_constants(expr, text, symbol):
    """Every constant part (a subexpression without t, such as exp(1000) or
    asin(2)) must be a finite real number in double precision, in which the
    curve is evaluated (SymPy keeps exp(1000) finite, NumPy makes it inf);
    the parts are evaluated by NumPy, as the curve will be."""
    stack = [expr]
    while stack:
        node = stack.pop()
        if not node.is_number:  # depends on t: look at its parts
            stack.extend(node.args)
            continue
        if node.is_Atom:  # a number (SymPy's exponents are unbounded), pi, e
            value = float(node)
        else:
            value = float(numeric_function(node, symbol)(np.array(0.0)))
        if not math.isfinite(value):
            raise ExpressionError(
                f"{text!r}: constant {node} is not a finite real number in "
                f"double precision (evaluates to {value})")


def numeric_function(expr, symbol):
    """A NumPy function of ``t`` for ``expr`` that broadcasts constants."""
    function = sympy.lambdify([symbol], expr, modules="numpy")

    def evaluate(t):
        t = np.asarray(t, dtype=float)
        with np.errstate(all="ignore"):
            value = np.asarray(function(t), dtype=float)
        return np.broadcast_to(value, t.shape).copy() if value.shape \
            != t.shape else value

    return evaluate
