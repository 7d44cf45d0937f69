"""Parse hal/stm32g4/stm32g474_regs.h: its #defines, their values and @svd tags.

Shared by gen_svd_subset.py (which registers to extract from the vendor SVD)
and check_regs.py (compare the header with the committed subset). Python
standard library only.
"""
import ast
import re

DEFINE_RE = re.compile(r"^\s*#\s*define\s+([A-Za-z_]\w*)(\([^)]*\))?\s*(.*?)\s*$")
COMMENT_RE = re.compile(r"/\*(.*?)\*/")
NUM_SUFFIX_RE = re.compile(r"\b(0[xX][0-9a-fA-F]+|\d+)[uUlL]+\b")
TAG_RE = re.compile(r"@(svd-shift|svd-base|svd-offset|svd|core|const)\b\s*(\S*)")
GUARD = "HAL_STM32G474_REGS_H"


class Define:
    def __init__(self, name, params, body, comment, line):
        self.name = name
        self.params = params
        self.body = body
        self.comment = comment
        self.line = line
        m = TAG_RE.search(comment or "")
        self.kind = m.group(1) if m else None
        self.target = m.group(2) if m else ""


def parse(path):
    """Return the list of Define in file order."""
    out = []
    with open(path, encoding="utf-8") as f:
        for lineno, raw in enumerate(f, 1):
            m = DEFINE_RE.match(raw)
            if not m:
                continue
            name, params, rest = m.group(1), m.group(2), m.group(3)
            comments = COMMENT_RE.findall(rest)
            body = COMMENT_RE.sub("", rest).strip()
            out.append(Define(name, params, body, " ".join(comments), lineno))
    return out


class Evaluator:
    """Evaluate object-like macro bodies: integers, + - * << >> | & ~ ( ),
    other macros, and REG32()/REG8() (which evaluate to their address)."""

    def __init__(self, defines):
        self.by_name = {d.name: d for d in defines if d.params is None}
        self.cache = {}

    def value(self, name, depth=0):
        if name in self.cache:
            return self.cache[name]
        if depth > 20 or name not in self.by_name:
            raise ValueError("cannot evaluate %s" % name)
        expr = self.by_name[name].body
        v = self.expr(expr, depth)
        self.cache[name] = v
        return v

    def expr(self, text, depth=0):
        text = re.sub(r"\bREG(32|8)\s*\(", "(", text)
        text = NUM_SUFFIX_RE.sub(r"\1", text)
        tree = ast.parse(text, mode="eval")
        return self._eval(tree.body, depth) & 0xFFFFFFFF

    def _eval(self, node, depth):
        if isinstance(node, ast.Constant) and isinstance(node.value, int):
            return node.value
        if isinstance(node, ast.Name):
            return self.value(node.id, depth + 1)
        if isinstance(node, ast.UnaryOp) and isinstance(node.op, ast.Invert):
            return ~self._eval(node.operand, depth) & 0xFFFFFFFF
        if isinstance(node, ast.BinOp):
            a, b = self._eval(node.left, depth), self._eval(node.right, depth)
            ops = {ast.Add: lambda: a + b, ast.Sub: lambda: a - b, ast.Mult: lambda: a * b,
                   ast.LShift: lambda: a << b, ast.RShift: lambda: a >> b, ast.BitOr: lambda: a | b,
                   ast.BitAnd: lambda: a & b}
            for t, f in ops.items():
                if isinstance(node.op, t):
                    return f()
        raise ValueError("unsupported expression: %s" % ast.dump(node))


def svd_refs(defines):
    """(peripheral, register or None, field or None) referenced by the tags."""
    refs = set()
    for d in defines:
        if not d.kind or not d.kind.startswith("svd"):
            continue
        path = d.target.split("=")[0].split(".")
        refs.add((path[0], path[1] if len(path) > 1 else None, path[2] if len(path) > 2 else None))
    return refs
