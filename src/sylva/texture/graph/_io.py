"""Graph files: TOML and JSON in, TOML and JSON out, with positions for errors (private).

``tomllib`` reports no positions of keys, so :func:`_locate_toml` finds them itself: it
scans the text for the ``[graph]`` and ``[nodes.NAME]`` table headers and the ``key =``
lines under them (keys written as dotted keys or in inline tables fall back to the position
of their table).  JSON positions come from a scan for ``"name": {`` and ``"key":``.
"""

from __future__ import annotations

import json
import math
import re
import tomllib
from pathlib import Path

from ._nodes import COLOUR, NODE_TYPES, GraphError, Node, _is_num

_HEAD = re.compile(r'^\s*\[\s*(?:"([^"]+)"|([A-Za-z0-9_-]+))'
                   r'(?:\s*\.\s*(?:"([^"]+)"|([A-Za-z0-9_-]+)))?\s*\]')
_KEY = re.compile(r'^(\s*)(?:"([^"]+)"|([A-Za-z0-9_-]+))\s*=\s*')


def _locate_toml(text, filename):
    """``{(table, key): where}`` and ``{table: where}`` for the text's tables and keys."""
    pos, lines = {}, text.splitlines()
    table = None
    in_block = None
    for n, line in enumerate(lines, 1):
        if in_block:
            if in_block in line:
                in_block = None
            continue
        m = _HEAD.match(line)
        if m and not line.lstrip().startswith("[["):
            a = m.group(1) or m.group(2)
            b = m.group(3) or m.group(4)
            table = (a, b) if b else (a,)
            pos[table] = dict(filename=filename, line=n, column=line.index("[") + 1,
                              source_line=line)
            continue
        m = _KEY.match(line)
        if m and table is not None:
            key = m.group(2) or m.group(3)
            vcol = m.end() + 1
            w = dict(filename=filename, line=n, column=vcol, source_line=line)
            rest = line[m.end():]
            for q in ("'''", '"""'):
                if rest.startswith(q):
                    if rest[3:].strip() == "":
                        w = dict(w, text_line=n + 1, text_column=1, block=True)
                    else:
                        w = dict(w, text_column=vcol + 3, block=False)
                    if rest.count(q) < 2:
                        in_block = q
                    break
            else:
                if rest[:1] in "\"'":
                    w = dict(w, block=False, text_column=vcol + 1)
            pos[table + (key,)] = w
    return pos


def _locate_json(text, filename):
    pos = {}
    lines = text.splitlines(keepends=True)
    starts = [0]
    for ln in lines:
        starts.append(starts[-1] + len(ln))

    def where(off, shift=0):
        import bisect

        n = bisect.bisect_right(starts, off) - 1
        return dict(filename=filename, line=n + 1, column=off - starts[n] + 1 + shift,
                    source_line=lines[n] if n < len(lines) else None)

    m = re.search(r'"nodes"\s*:\s*\{', text)
    if m:
        heads = [(h.group(1), h.start()) for h in re.finditer(r'"([^"]+)"\s*:\s*\{', text)
                 if h.start() > m.start()]
        for k, (name, at) in enumerate(heads):
            end = heads[k + 1][1] if k + 1 < len(heads) else len(text)
            pos[("nodes", name)] = where(at)
            for km in re.finditer(r'"([^"]+)"\s*:\s*', text[at:end]):
                if km.start() == 0:
                    continue
                pos.setdefault(("nodes", name, km.group(1)),
                               dict(where(at + km.end()), block=False,
                                    text_column=where(at + km.end())["column"] + 1))
    g = re.search(r'"graph"\s*:\s*\{', text)
    if g:
        pos[("graph",)] = where(g.start())
        for km in re.finditer(r'"([^"]+)"\s*:\s*', text[g.end():]):
            pos.setdefault(("graph", km.group(1)), where(g.end() + km.end()))
    return pos


def loads(text, *, fmt="toml", filename=None):
    """Read a graph from TOML or JSON text; see :func:`sylva.texture.graph.load`."""
    from . import Graph

    filename = filename or f"<{fmt}>"
    if fmt == "toml":
        try:
            data = tomllib.loads(text)
        except tomllib.TOMLDecodeError as exc:
            msg = str(exc)
            m = re.search(r"\(at line (\d+), column (\d+)\)", msg)
            line, col = (int(m.group(1)), int(m.group(2))) if m else (None, None)
            lines = text.splitlines()
            src = lines[line - 1] if line and 0 < line <= len(lines) else None
            raise GraphError(f"not valid TOML: {re.sub(r' [(]at line.*', '', msg)}",
                             filename=filename, line=line, column=col, source_line=src) from None
        pos = _locate_toml(text, filename)
    elif fmt == "json":
        try:
            data = json.loads(text)
        except json.JSONDecodeError as exc:
            lines = text.splitlines()
            src = lines[exc.lineno - 1] if 0 < exc.lineno <= len(lines) else None
            raise GraphError(f"not valid JSON: {exc.msg}", filename=filename, line=exc.lineno,
                             column=exc.colno, source_line=src) from None
        pos = _locate_json(text, filename)
    else:
        raise GraphError(f"unknown graph format {fmt!r}; expected toml or json")
    top = dict(filename=filename, line=1, column=1)
    if not isinstance(data, dict):
        raise GraphError("a graph file holds a table", **top)
    props = data.get("graph", {})
    nodes = data.get("nodes")
    gpos = pos.get(("graph",), top)
    if not isinstance(props, dict):
        raise GraphError("[graph] must be a table", **gpos)
    if not isinstance(nodes, dict) or not nodes:
        raise GraphError("a graph needs a [nodes.NAME] table per node", **top)
    extra = set(data) - {"graph", "nodes"}
    if extra:
        raise GraphError(f"unknown top-level table(s) {', '.join(sorted(extra))}; expected "
                         "[graph] and [nodes.NAME]", **top)
    built, names, state = {}, {}, {}

    def nodepos(name, key=None):
        if key is not None and ("nodes", name, key) in pos:
            return pos[("nodes", name, key)]
        return pos.get(("nodes", name), top)

    def build(name, via):
        if state.get(name) == "busy":
            w = via or nodepos(name)
            raise GraphError(f"the graph has a cycle through node {name!r}; a graph must be "
                             "acyclic (no node may feed itself)", **w)
        if name in built:
            return built[name]
        state[name] = "busy"
        body = nodes[name]
        if not isinstance(body, dict):
            raise GraphError(f"node {name!r} must be a table", **nodepos(name))
        typ = body.get("type")
        where = {k: nodepos(name, k) for k in body}
        where.setdefault("type", nodepos(name))
        where["_node"] = nodepos(name)
        if typ is None:
            raise GraphError(f"node {name!r} needs a type (one of: "
                             f"{', '.join(sorted(NODE_TYPES))})", **nodepos(name))
        if typ not in NODE_TYPES:
            raise GraphError(f"node {name!r}: unknown node type {typ!r}; expected one of: "
                             f"{', '.join(sorted(NODE_TYPES))}", **nodepos(name, "type"))
        spec = NODE_TYPES[typ]
        slots = {n: t for n, t, _ in spec.inputs}
        inputs, params = {}, {}
        for k, v in body.items():
            if k == "type":
                continue
            if k in slots:
                if isinstance(v, str):
                    if v not in nodes:
                        raise GraphError(
                            f"input {k!r} of node {name!r} names an unknown node {v!r}; "
                            f"expected one of the nodes: {', '.join(sorted(nodes))} or a "
                            "number", **nodepos(name, k))
                    src = build(v, nodepos(name, k))
                    got = src.spec.output
                    if got != slots[k]:
                        raise GraphError(
                            f"input {k!r} of node {name!r} ({typ}) takes a {slots[k]}, but "
                            f"node {v!r} ({src.type}) gives a {got}", **nodepos(name, k))
                    inputs[k] = src
                elif _is_num(v) and slots[k] != COLOUR:
                    inputs[k] = float(v)
                else:
                    want = "a node name" if slots[k] == COLOUR else "a node name or a number"
                    raise GraphError(f"input {k!r} of node {name!r} ({typ}) must be {want}, "
                                     f"got {v!r}", **nodepos(name, k))
            else:
                params[k] = v
        node = Node(typ, inputs, params, where)
        built[name] = node
        names[id(node)] = name
        state[name] = "done"
        return node

    for name in nodes:
        build(name, None)
    out = props.get("output")
    if out is None:
        users = {id(v) for n in built.values() for v in n.inputs.values()}
        roots = [n for n in nodes if id(built[n]) not in users]
        if len(roots) != 1:
            raise GraphError(f"say which node is the output ([graph] output = NAME); the "
                             f"graph ends in {len(roots)} nodes: {', '.join(roots)}", **gpos)
        out = roots[0]
    if out not in built:
        raise GraphError(f"[graph] output names an unknown node {out!r}; expected one of: "
                         f"{', '.join(sorted(nodes))}", **pos.get(("graph", "output"), gpos))
    kw = {k: v for k, v in props.items() if k != "output"}
    return Graph._from_props(built[out], kw, names, {k[1]: v for k, v in pos.items()
                                                     if k[0] == "graph" and len(k) == 2},
                             gpos)


def load(path):
    """Read a graph file (``.toml`` or ``.json``)."""
    path = Path(path)
    try:
        text = path.read_text(encoding="utf-8")
    except OSError as exc:
        raise GraphError(f"cannot read graph file: {exc.strerror or exc}",
                         filename=str(path)) from None
    fmt = "json" if path.suffix.lower() == ".json" else "toml"
    return loads(text, fmt=fmt, filename=str(path))


# ----------------------------------------------------------------------------- writing
def _tv(v):
    if isinstance(v, bool):
        return "true" if v else "false"
    if isinstance(v, int):
        return str(v)
    if isinstance(v, float):
        if math.isnan(v) or math.isinf(v):
            return "nan" if math.isnan(v) else ("inf" if v > 0 else "-inf")
        return repr(v)
    if isinstance(v, str):
        if "\n" in v and "'''" not in v:
            return "'''\n" + v + "'''"
        esc = v.replace("\\", "\\\\").replace('"', '\\"').replace("\n", "\\n")
        return f'"{esc}"'
    if isinstance(v, list | tuple):
        return "[" + ", ".join(_tv(x) for x in v) + "]"
    if isinstance(v, dict):
        return "{ " + ", ".join(f"{_tk(k)} = {_tv(x)}" for k, x in v.items()
                                if x is not None) + " }"
    raise GraphError(f"cannot write a {type(v).__name__} value ({v!r}) to a graph file")


def _tk(k):
    k = str(k)
    if k and all(c.isalnum() or c in "-_" for c in k):
        return k
    return json.dumps(k)


def _clean(v):
    if isinstance(v, tuple):
        return [_clean(x) for x in v]
    if isinstance(v, list):
        return [_clean(x) for x in v]
    if isinstance(v, dict):
        return {str(k): _clean(x) for k, x in v.items() if x is not None}
    if hasattr(v, "item"):
        return v.item()
    return v


def to_dict(graph):
    """The graph as plain data: ``{"graph": {...}, "nodes": {name: {...}}}``."""
    from ._nodes import walk

    order = walk(graph.output)
    names, used = {}, set()
    for k, n in enumerate(order):
        name = graph.names.get(id(n)) or ("out" if n is graph.output else f"{n.type}{k}")
        while name in used:
            name += "_"
        used.add(name)
        names[id(n)] = name
    nodes = {}
    for n in order:
        body = {"type": n.type}
        for k, v in n.inputs.items():
            body[k] = names[id(v)] if isinstance(v, Node) else float(v)
        for k, v in n.params.items():
            if v is not None:
                body[k] = _clean(v)
        nodes[names[id(n)]] = body
    props = {"output": names[id(graph.output)], **_clean(graph._props())}
    return {"graph": props, "nodes": nodes}


def dumps(graph, fmt="toml"):
    """The graph as TOML or JSON text."""
    d = to_dict(graph)
    if fmt == "json":
        return json.dumps(d, indent=2) + "\n"
    lines = ["[graph]"]
    lines += [f"{_tk(k)} = {_tv(v)}" for k, v in d["graph"].items()]
    for name, body in d["nodes"].items():
        lines += ["", f"[nodes.{_tk(name)}]"]
        lines += [f"{_tk(k)} = {_tv(v)}" for k, v in body.items()]
    return "\n".join(lines) + "\n"
