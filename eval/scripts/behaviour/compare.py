#!/usr/bin/env python3
"""Compare the outputs of run_commit.sh for two commits (stdlib only).

Usage: compare.py [DIR_A] [DIR_B]   (default /work/cmp/8ea9a58 /work/cmp/471cf30)

Timing figures are stripped before comparing: JSON keys and CSV columns whose
name has a token timing/seconds/secs/ms/us/rate/elapsed/load/wall or the
part per_s (tokens split on '_', '-', '.', camelCase; so `objective_terms` or
`surface` are kept, `plan_seconds` is dropped), and in Markdown every number
followed by a time unit (s, ms, µs), "N ×" speed-up ratios, load averages and
the "Made by ..." command line. Everything stripped is listed, so nothing is
hidden. Every other figure must be bit-identical (floats compared as parsed
from the JSON text) for "identical"; differences are listed with abs/rel size.
"""
import csv, hashlib, io, json, os, re, sys

A = sys.argv[1] if len(sys.argv) > 1 else "/work/cmp/8ea9a58"
B = sys.argv[2] if len(sys.argv) > 2 else "/work/cmp/471cf30"
# Not "time": `total_time_s` (a plan's total dig duration) and `time_samples`
# (the model's step count) are behaviour; the computation timings are all
# named with seconds/elapsed/wall/per_s (checked over every key written).
# `speedup`: ratios of two timings (speedup_vs_pso).
TIMING_TOKENS = {"timing", "timings", "seconds", "secs", "ms", "us",
                 "rate", "elapsed", "load", "wall", "speedup"}
# pipeline.json's `steps`: [name, wall seconds] pairs (PipelineOutcome::steps).
TIMING_KEYS = {"steps"}
# Files that are pictures of timings only (the dig time distribution).
TIMING_FILES = {"dig_time.svg"}
stripped = {}
# Output folders are named after the commit; that name is not behaviour.
COMMIT_DIR = re.compile(r"/work/cmp/[0-9a-f]{7}")  # file kind -> set of stripped key paths


def tokens(key):
    key = re.sub(r"([a-z0-9])([A-Z])", r"\1_\2", str(key)).lower()
    return [t for t in re.split(r"[_\-.\s]+", key) if t]


def is_timing(key):
    k = str(key).lower()
    return bool(set(tokens(key)) & TIMING_TOKENS) or re.search(r"(^|_)per_s($|_)", k) is not None


def strip(o, path, kind):
    if isinstance(o, dict):
        out = {}
        for k, v in o.items():
            p = f"{path}.{k}"
            if is_timing(k) or k in TIMING_KEYS:
                stripped.setdefault(kind, set()).add(re.sub(r"\[\d+\]", "[]", p))
            else:
                out[k] = strip(v, p, kind)
        return out
    if isinstance(o, list):
        return [strip(v, f"{path}[{i}]", kind) for i, v in enumerate(o)]
    if isinstance(o, str):
        # Strings such as the goals' "measured" ("12 × (450.6 ms vs 38768.9 µs)"):
        # time figures masked as in Markdown.
        masked = mask_md(o)[0] if o else o
        if masked != o and not COMMIT_DIR.search(o):
            stripped.setdefault(kind, set()).add(re.sub(r"\[\d+\]", "[]", path) + " (time figures in the text masked)")
        return masked
    return o


def leaf_diffs(a, b, path=""):
    if isinstance(a, dict) and isinstance(b, dict):
        for k in sorted(set(a) | set(b), key=str):
            if k not in a or k not in b:
                yield (f"{path}.{k}", a.get(k, "<absent>"), b.get(k, "<absent>"))
            else:
                yield from leaf_diffs(a[k], b[k], f"{path}.{k}")
    elif isinstance(a, list) and isinstance(b, list):
        if len(a) != len(b):
            yield (f"{path}.len", len(a), len(b))
        for i, (x, y) in enumerate(zip(a, b)):
            yield from leaf_diffs(x, y, f"{path}[{i}]")
    elif a != b or type(a) is not type(b):
        yield (path, a, b)


def fmt_diff(p, x, y):
    if isinstance(x, (int, float)) and isinstance(y, (int, float)) and not isinstance(x, bool):
        d = y - x
        rel = abs(d) / max(abs(x), abs(y)) if max(abs(x), abs(y)) > 0 else 0.0
        return f"{p}: {x!r} -> {y!r} (diff {d:.3g}, rel {rel:.2e})", rel
    return f"{p}: {str(x)[:120]!r} -> {str(y)[:120]!r}", float("inf")


EVALS = re.compile(r"\.digs\[\d+\]\.evaluations$")


def cmp_json(fa, fb, kind, show=8):
    a = strip(json.load(open(fa)), "", kind)
    b = strip(json.load(open(fb)), "", kind)
    diffs = list(leaf_diffs(a, b))
    if not diffs:
        return "identical (timings stripped)", []
    lines = [fmt_diff(*d) for d in diffs]
    maxrel = max(r for _, r in lines)
    if all(EVALS.search(p) for p, _, _ in diffs):
        steps = sorted(set(y - x for _, x, y in diffs))
        return f"identical but for the exact-evaluation count of {len(diffs)} digs (change {steps})", []
    head = f"DIFFER: {len(diffs)} figures, max rel {maxrel:.2e}"
    return head, [l for l, _ in lines][:show]


def cmp_csv(fa, fb, show=8):
    ra = list(csv.reader(open(fa, newline="")))
    rb = list(csv.reader(open(fb, newline="")))
    if not ra or not rb:
        return ("identical" if ra == rb else "DIFFER (empty)"), []
    keep_a = [i for i, h in enumerate(ra[0]) if not is_timing(h)]
    keep_b = [i for i, h in enumerate(rb[0]) if not is_timing(h)]
    dropped = sorted(set(h for h in ra[0] if is_timing(h)))
    if dropped:
        stripped.setdefault("csv columns", set()).update(dropped)
    ta = [[r[i] if i < len(r) else "" for i in keep_a] for r in ra]
    tb = [[r[i] if i < len(r) else "" for i in keep_b] for r in rb]
    if ta == tb:
        return "identical (timing columns stripped)", []
    out = []
    for n, (x, y) in enumerate(zip(ta, tb)):
        for h, u, v in zip(ta[0], x, y):
            if u != v:
                out.append(f"row {n} ({x[0]}) {h}: {u} -> {v}")
    if len(ta) != len(tb):
        out.append(f"rows {len(ta)} -> {len(tb)}")
    return f"DIFFER: {len(out)} cells", out[:show]


MD_MASKS = [
    (COMMIT_DIR, "/work/cmp/<C>"),
    (re.compile(r"^Made by .*$"), "Made by <command, wall time, load average>"),
    (re.compile(r"load average[^)]*"), "load average <L>"),
    (re.compile(r"[\d][\d,]*(\.\d+)?\s*(ms|µs|us|s)\b"), "<T>"),
    (re.compile(r"[\d][\d,]*(\.\d+)?\s*×"), "<N ×>"),
]


def mask_md(text):
    out = []
    for line in text.splitlines():
        for rx, rep in MD_MASKS:
            line = rx.sub(rep, line)
        out.append(line)
    return out


def cmp_md(fa, fb, show=12):
    la, lb = mask_md(open(fa).read()), mask_md(open(fb).read())
    if la == lb:
        return "identical (timings masked)", []
    import difflib
    d = [l for l in difflib.unified_diff(la, lb, "a", "b", n=0, lineterm="")
         if not l.startswith(("---", "+++", "@@"))]
    return f"DIFFER: {sum(1 for l in d if l.startswith('-'))} lines", d[:show]


def mcap_messages(path):
    """(topic, sequence, log_time, publish_time, data) of every message of an
    MCAP file, chunks opened (uncompressed only), in file order; plus the
    schema and channel records. Stdlib reader of the MCAP record layout."""
    import struct
    b = open(path, "rb").read()
    assert b[:8] == b"\x89MCAP0\r\n", path
    channels, out, meta = {}, [], []

    def records(buf, pos, end):
        while pos + 9 <= end:
            op = buf[pos]
            (n,) = struct.unpack_from("<Q", buf, pos + 1)
            yield op, buf[pos + 9: pos + 9 + n]
            pos += 9 + n

    def walk(buf):
        for op, c in records(buf, 0, len(buf)):
            if op == 0x03:  # schema
                meta.append(("schema", bytes(c)))
            elif op == 0x04:  # channel: id u16, schema_id u16, topic string
                cid, _sid, tl = struct.unpack_from("<HHI", c, 0)
                channels[cid] = bytes(c[8:8 + tl]).decode()
                meta.append(("channel", bytes(c)))
            elif op == 0x05:  # message
                cid, seq, lt, pt = struct.unpack_from("<HIQQ", c, 0)
                out.append((channels.get(cid, cid), seq, lt, pt, bytes(c[22:])))
            elif op == 0x06:  # chunk
                p = 8 + 8 + 8 + 4
                (cl,) = struct.unpack_from("<I", c, p)
                comp = bytes(c[p + 4: p + 4 + cl]).decode()
                p += 4 + cl
                (rl,) = struct.unpack_from("<Q", c, p)
                assert comp == "", f"{path}: compressed chunk ({comp})"
                walk(c[p + 8: p + 8 + rl])
            elif op == 0x0F:  # data end
                break
    walk(memoryview(b)[8:])
    return meta, out


WALL = re.compile(rb'"wall_time_s":-?[0-9.eE+-]+')


def mcap_digest(path):
    """sha256 of every schema, channel and message record, byte for byte,
    with each sample's `wall_time_s` value (its optimisation's wall time,
    documented as the only field that differs between runs) set to 0."""
    meta, msgs = mcap_messages(path)
    h = hashlib.sha256()
    for kind, c in meta:
        h.update(kind.encode() + c)
    walls = []
    for topic, seq, lt, pt, data in msgs:
        m = WALL.search(data)
        if m:
            walls.append(float(m.group(0).split(b":")[1]))
        h.update(f"{topic}|{seq}|{lt}|{pt}|".encode() + WALL.sub(b'"wall_time_s":0', data))
    return h.hexdigest(), len(msgs), walls


def sha(f):
    return hashlib.sha256(open(f, "rb").read()).hexdigest()


def cmp_file(fa, fb, kind):
    ext = os.path.splitext(fa)[1]
    if os.path.basename(fa) in TIMING_FILES:
        stripped.setdefault("files", set()).add(os.path.basename(fa))
        return "identical (not compared: a picture of timings)", []
    if ext == ".json":
        return cmp_json(fa, fb, kind)
    if ext == ".csv":
        return cmp_csv(fa, fb)
    if ext == ".stdout":
        try:
            json.load(open(fa)); json.load(open(fb))
            return cmp_json(fa, fb, kind)
        except ValueError:
            return cmp_md(fa, fb)
    if ext == ".md":
        return cmp_md(fa, fb)
    same = sha(fa) == sha(fb)
    return ("identical bytes" if same else "DIFFER (bytes)"), []


def report(title, fa, fb, kind):
    if not (os.path.exists(fa) and os.path.exists(fb)):
        print(f"  {title}: MISSING ({fa if not os.path.exists(fa) else fb})")
        return False
    head, lines = cmp_file(fa, fb, kind)
    print(f"  {title}: {head}")
    for l in lines:
        print(f"      {l}")
    EVAL_ONLY.update([title] if "but for" in head else [])
    return head.startswith("identical")


EVAL_ONLY = set()  # outputs identical but for .digs[].evaluations


def files_under(d):
    return sorted(os.path.relpath(os.path.join(r, f), d) for r, _, fs in os.walk(d) for f in fs)


def main():
    ca, cb = os.path.basename(A), os.path.basename(B)
    ok = {}
    print(f"# {ca} (A) vs {cb} (B)\n")
    print("## Plans A-D (plan --task X [-o]; network, and --templates artifacts/templates.json)")
    for d, c in ((A, ca), (B, cb)):
        same = all(cmp_file(f"{d}/plan_{t}_{p}_r1{e}", f"{d}/plan_{t}_{p}_r2{e}", "plan")[0]
                   .startswith("identical") for t in "ABCD" for p in ("network", "templates")
                   for e in (".json", ".svg"))
        print(f"  control, {c} run 1 vs run 2 (json + svg, 8 plans): {'identical' if same else 'DIFFER'}")
    res = []
    for t in "ABCD":
        for p in ("network", "templates"):
            for e in (".json", ".svg"):
                res.append(report(f"plan_{t}_{p}{e}", f"{A}/plan_{t}_{p}_r1{e}", f"{B}/plan_{t}_{p}_r1{e}", "plan"))
    ok["plans"] = all(res)

    print("\n## Dataset (dataset_gen generate --seed 7 --per-type 24 --part-size 16 --algorithm pso, --threads 1 and 2)")
    print("  raw sha256 of the .mcap files (parts and merged dataset.mcap):")
    for d, c in ((A, ca), (B, cb)):
        for th in ("1", "2"):
            for f in [f for f in files_under(f"{d}/ds_t{th}") if f.endswith(".mcap")]:
                print(f"    {c} ds_t{th}/{f} {sha(os.path.join(d, 'ds_t' + th, f))}")
    print("  sha256 of the records with wall_time_s zeroed (see mcap_digest):")
    dig = {}
    for d, c in ((A, ca), (B, cb)):
        for th in ("1", "2"):
            for f in [f for f in files_under(f"{d}/ds_t{th}") if f.endswith(".mcap")]:
                h, n, walls = mcap_digest(os.path.join(d, "ds_t" + th, f))
                dig[(d, th, f)] = h
                print(f"    {c} ds_t{th}/{f} {h} ({n} messages; wall_time_s {min(walls, default=0):.3f}-{max(walls, default=0):.3f} s)")
    res = []
    for (d1, t1), (d2, t2) in [((A, "1"), (A, "2")), ((B, "1"), (B, "2")), ((A, "1"), (B, "1")), ((A, "2"), (B, "2"))]:
        f1 = sorted(f for (d, t, f) in dig if d == d1 and t == t1)
        f2 = sorted(f for (d, t, f) in dig if d == d2 and t == t2)
        raw = f1 == f2 and all(sha(f"{d1}/ds_t{t1}/{f}") == sha(f"{d2}/ds_t{t2}/{f}") for f in f1)
        same = f1 == f2 and all(dig[(d1, t1, f)] == dig[(d2, t2, f)] for f in f1)
        res.append(same)
        print(f"  {os.path.basename(d1)} t{t1} vs {os.path.basename(d2)} t{t2} ({len(f1)} files): "
              f"raw bytes {'identical' if raw else 'differ'}; wall_time_s zeroed: {'IDENTICAL' if same else 'DIFFER'}")
    for d, c in ((A, ca), (B, cb)):
        pass
    for th in ("1", "2"):
        res.append(report(f"manifest.json t{th}", f"{A}/ds_t{th}/manifest.json", f"{B}/ds_t{th}/manifest.json", "dataset manifest"))
        res.append(report(f"generate stdout (summary JSON) t{th}", f"{A}/ds_t{th}.stdout", f"{B}/ds_t{th}.stdout", "generate summary"))
    ok["dataset"] = all(res)

    print("\n## eval pipeline --quick (report folder and working folder)")
    fa, fb = files_under(f"{A}/quick"), files_under(f"{B}/quick")
    for f in sorted(set(fa) ^ set(fb)):
        print(f"  only in {'A' if f in fa else 'B'}: {f}")
    res = [set(fa) == set(fb)]
    for f in sorted(set(fa) & set(fb)):
        res.append(report(f, f"{A}/quick/{f}", f"{B}/quick/{f}", "quick " + os.path.splitext(f)[1]))
    res.append(report("console output (stdout)", f"{A}/quick.stdout", f"{B}/quick.stdout", "stdout"))
    ok["quick"] = all(res)

    print("\n## Extra, not in issue 23's list: offline sequence PSO (dataset_gen optimise-task --task B, small budget)")
    for f in ("seq_B.json", "seq_B.stdout"):
        if os.path.exists(f"{A}/{f}") or os.path.exists(f"{B}/{f}"):
            report(f, f"{A}/{f}", f"{B}/{f}", "sequence plan")

    print("\n## Extra, not in issue 23's list: plans A-D under an evaluation bound (plan --settings bound/settings.json, max_evaluations 320)")
    for t in "ABCD":
        fa, fb = f"{A}/../bound/{os.path.basename(A)}_{t}.json", f"{B}/../bound/{os.path.basename(B)}_{t}.json"
        if os.path.exists(fa) and os.path.exists(fb):
            report(f"bound plan {t}", fa, fb, "plan")

    print("\n## Pinned evaluation hash (infer/tests/dig.rs evaluation_numbers_are_pinned_to_the_bit)")
    for d, c in ((A, ca), (B, cb)):
        p = f"{d}/pinned_test.log"
        txt = open(p).read() if os.path.exists(p) else ""
        m = re.search(r"test result: (\w+)\. (\d+) passed; (\d+) failed", txt)
        print(f"  {c}: {m.group(0) if m else 'no log'}")
    ok["pinned"] = all(os.path.exists(f"{d}/pinned_test.log") and
                       "test result: ok. 1 passed" in open(f"{d}/pinned_test.log").read() for d in (A, B))

    print("\n## Stripped as timing (not compared)")
    for k in sorted(stripped):
        print(f"  {k}: " + ", ".join(sorted(stripped[k])))
    print(f"\n{len(EVAL_ONLY)} JSON outputs (plans and the bound probe) are identical but for the per-dig count of exact evaluations.")
    print("## Summary (issue 23's list; evaluation counts aside): " + ", ".join(f"{k} {'identical' if v else 'DIFFER'}" for k, v in ok.items()))


if __name__ == "__main__":
    main()
