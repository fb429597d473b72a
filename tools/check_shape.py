#!/usr/bin/env python3
"""check_shape.py - the build's size check of the code (docs/architecture.md,
"Size rules"; issue 26).

Three rules over the C sources under src/:

1. no function longer than FUNC_MAX lines (signature to closing brace);
2. no source file of the FE module (src/fem) longer than FE_FILE_MAX lines;
3. no struct of the FE module with more than FE_STRUCT_MAX members (a run
   state groups its members into named sub-structs instead).

Comments and string literals are blanked before the braces are counted, so a
brace in a comment or a string does not count.

Usage: check_shape.py SOURCE_DIR      (exit 1 on a violation)
       check_shape.py --selftest      (the checker on made-up sources)
"""
import os
import re
import sys

FUNC_MAX = 100
FE_FILE_MAX = 600
FE_STRUCT_MAX = 30

TOKEN_RE = re.compile(r'//[^\n]*|/\*.*?\*/|"(?:\\.|[^"\\\n])*"|\'(?:\\.|[^\'\\\n])*\'', re.S)


def blank(text):
    """text with comments, strings and character literals replaced by spaces (newlines kept)."""
    return TOKEN_RE.sub(lambda m: re.sub(r"[^\n]", " ", m.group(0)), text)


def top_level_blocks(code):
    """(kind, name, first line, last line, members) of every top-level brace block:
    kind 'function' or 'struct'; members = the names declared directly inside (structs)."""
    blocks, depth, paren, start, head_from, semis = [], 0, 0, 0, 0, 0
    line = 1
    for i, ch in enumerate(code):
        if ch == "\n":
            line += 1
        elif ch == "{":
            if depth == 0:
                start, semis = i, 0
            depth += 1
        elif ch == "}":
            depth -= 1
            if depth == 0:
                head = code[head_from:start]
                blocks.append(classify(head, code, head_from, start, i, semis))
                head_from = i + 1
        elif ch in "([":
            paren += 1
        elif ch in ")]":
            paren -= 1
        elif ch == "," and depth == 1 and paren == 0:
            semis += 1  # double *u, *v: two members
        elif ch == ";":
            if depth == 0:
                head_from = i + 1
            elif depth == 1:
                semis += 1
    return [b for b in blocks if b]


def classify(head, code, head_from, start, end, semis):
    first = code.count("\n", 0, head_from + len(head) - len(head.lstrip())) + 1
    last = code.count("\n", 0, end) + 1
    h = " ".join(head.split())
    if re.search(r"\bstruct\b[^(]*$", h) and "=" not in h:
        name = re.sub(r".*\bstruct\s*", "", h).strip()
        if not name:  # typedef struct { ... } name;
            m = re.match(r"\s*(\w+)", code[end + 1:end + 200])
            name = m.group(1) if m else "(anonymous)"
        return ("struct", name, first, last, semis)
    m = re.search(r"(\w+)\s*\([^=]*\)\s*$", h)
    if m and "=" not in h:
        return ("function", m.group(1), first, last, 0)
    return None


def check_file(path, rel, fe):
    with open(path, encoding="utf-8", errors="replace") as f:
        text = f.read()
    bad = []
    nlines = text.count("\n")
    if fe and path.endswith(".c") and nlines > FE_FILE_MAX:
        bad.append(f"{rel}: {nlines} lines (an FE source file has at most {FE_FILE_MAX})")
    code = blank(text)
    code = re.sub(r"^[ \t]*#(?:[^\n]*\\\n)*[^\n]*", lambda m: re.sub(r"[^\n]", " ", m.group(0)), code, flags=re.M)
    for kind, name, first, last, semis in top_level_blocks(code):
        n = last - first + 1
        if kind == "function" and n > FUNC_MAX:
            bad.append(f"{rel}:{first}: function {name} has {n} lines (at most {FUNC_MAX})")
        if kind == "struct" and fe and semis > FE_STRUCT_MAX:
            bad.append(f"{rel}:{first}: struct {name} has {semis} members (at most {FE_STRUCT_MAX}: group them)")
    return bad


def check_tree(root):
    bad = []
    src = os.path.join(root, "src")
    for d, _, files in sorted(os.walk(src)):
        for fn in sorted(files):
            if fn.endswith((".c", ".h")):
                p = os.path.join(d, fn)
                rel = os.path.relpath(p, root)
                bad += check_file(p, rel, rel.startswith(os.path.join("src", "fem") + os.sep))
    return bad


def selftest():
    import tempfile
    long_body = "\n".join(f"    x += {i}; /* {{ */" for i in range(FUNC_MAX))
    cases = {
        "ok.c": "static int f(int x)\n{\n    const char *s = \"}}}\";\n    return x;\n}\n",
        "long.c": f"int g(int x)\n{{\n{long_body}\n    return x;\n}}\n",
        "init.c": "static const int t[] = {\n" + "1,\n" * 200 + "};\n",
    }
    members = "\n".join(f"    double m{i};" for i in range(FE_STRUCT_MAX + 1))
    fe_cases = {"wide.c": f"typedef struct {{\n{members}\n}} run;\n", "big.c": "int a;\n" * (FE_FILE_MAX + 1)}
    with tempfile.TemporaryDirectory() as t:
        for sub, cs in (("src/x", cases), ("src/fem", fe_cases)):
            os.makedirs(os.path.join(t, sub))
            for fn, body in cs.items():
                with open(os.path.join(t, sub, fn), "w") as f:
                    f.write(body)
        bad = check_tree(t)
    want = ["long.c:1: function g", "wide.c:1: struct run", "big.c: 601 lines"]
    missing = [w for w in want if not any(w in b for b in bad)]
    extra = [b for b in bad if not any(w in b for w in want)]
    for m in missing:
        print("selftest: not found:", m)
    for e in extra:
        print("selftest: false alarm:", e)
    return 1 if missing or extra or len(bad) != len(want) else 0


def main(argv):
    if len(argv) == 2 and argv[1] == "--selftest":
        rc = selftest()
        print("check_shape selftest:", "ok" if rc == 0 else "FAILED")
        return rc
    if len(argv) != 2:
        print(__doc__)
        return 2
    bad = check_tree(argv[1])
    for b in bad:
        print(b)
    print(f"check_shape: {len(bad)} violation(s)")
    return 1 if bad else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
