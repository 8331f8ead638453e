#!/usr/bin/env python3
"""The two-sided bound on every test model, before and after, in one Markdown table.

For every model (*.obj in --models) at --eps-diag F, and for the extra absolute tolerances given
with --extra-eps (default: the bunny at the thesis's Table 3.1 eps = 0.0003), this runs

  before: splatcl splats MODEL --thesis-only --samples vertices --eps-diag F -o OUT --stats S
          (the thesis's method alone; its end-of-run check only reports; should a build exit 1
          anyway without writing its output, it is re-run with --no-check when splatcl has it)
  after:  splatcl splats MODEL --eps-diag F -o OUT --stats S   (the default two-sided variant)

then `splatcl splats verify MODEL OUT --json J` on both (exit 1 is expected for "before"; the JSON
is read either way), and prints one table row per model and variant, followed by the mesh warnings
that `splatcl splats` printed and the machine's load average while it ran.

Relative paths are taken from the repository root (the parent of this script's folder), and every
command runs there, so the paths in the output are the ones given. Python 3 standard library only.
Exit status: 0 when every "after" run builds and verifies, 1 otherwise (the table is printed anyway,
with the failures listed under it).
"""
import argparse
import datetime
import json
import os
import platform
import shlex
import subprocess
import sys
import time

REPO = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))


def repo_path(path):
    return path if os.path.isabs(path) else os.path.normpath(os.path.join(REPO, path))


def log(message):
    print(message, file=sys.stderr, flush=True)


class LoadSampler:
    """Load averages (1 min) taken around every command."""

    def __init__(self):
        self.values = []

    def sample(self):
        try:
            self.values.append(os.getloadavg()[0])
        except OSError:
            pass

    def describe(self):
        if not self.values:
            return "unknown"
        v = self.values
        return f"{min(v):.1f}–{max(v):.1f} (mean {sum(v) / len(v):.1f}, 1-minute average, {len(v)} samples)"


def run(cmd, load, dry_run=False):
    """Runs cmd in the repository root; returns (rc, stdout, stderr, wall seconds)."""
    log("$ " + shlex.join(cmd))
    if dry_run:
        return 0, "", "", 0.0
    load.sample()
    start = time.monotonic()
    proc = subprocess.run(cmd, cwd=REPO, capture_output=True, text=True)
    wall = time.monotonic() - start
    load.sample()
    if proc.returncode != 0:
        log(f"  exit {proc.returncode}: {proc.stderr.strip().splitlines()[-1] if proc.stderr.strip() else ''}")
    return proc.returncode, proc.stdout, proc.stderr, wall


def mesh_messages(stderr):
    """The warning and note lines `splatcl splats` printed (progress lines are dropped)."""
    lines = []
    for raw in stderr.replace("\r", "\n").splitlines():
        line = raw.strip()
        if line.startswith("splatcl: warning:") or line.startswith("splatcl: note:"):
            lines.append(line)
    return lines


def read_json(path):
    try:
        with open(path) as f:
            return json.load(f)
    except (OSError, ValueError):
        return None


def has_flag(splatcl, flag):
    proc = subprocess.run([splatcl, "splats", "--help"], cwd=REPO, capture_output=True, text=True)
    return flag in proc.stdout


def fmt_count(n):
    return f"{n:,}"


def fmt_g(x, digits=3):
    if x == 0:
        return "0"
    return f"{x:.{digits}g}"


def run_case(args, load, model, variant, eps_args, tag, no_check_flag):
    """Builds and verifies one (model, variant, eps); returns a result dict."""
    name = os.path.splitext(os.path.basename(model))[0]
    stem = os.path.join(args.out, f"{name}-{tag}-{variant}")
    ply, stats, verify_json = stem + ".ply", stem + ".stats.json", stem + ".verify.json"
    cmd = [args.splatcl, "splats", model]
    if variant == "before":
        cmd += ["--thesis-only", "--samples", "vertices"]
    cmd += eps_args + ["-o", ply, "--stats", stats]
    if args.device:
        cmd += ["--device", args.device]
    result = {"model": name, "variant": variant, "tag": tag, "build_command": shlex.join(cmd), "ply": ply}
    reuse = args.reuse and all(os.path.exists(repo_path(p)) for p in (ply, stats, verify_json))
    if reuse:
        log(f"reusing {ply}")
        rc, err = 0, ""
        try:
            with open(repo_path(stem + ".stderr.txt")) as f:
                err = f.read()
        except OSError:
            pass
    else:
        for path in (ply, stats, verify_json):
            if os.path.exists(repo_path(path)):
                os.remove(repo_path(path))
        rc, out, err, wall = run(cmd, load, args.dry_run)
        if variant == "before" and rc != 0 and not os.path.exists(repo_path(ply)) and no_check_flag:
            cmd.append("--no-check")
            result["build_command"] = shlex.join(cmd)
            rc, out, err, wall = run(cmd, load, args.dry_run)
        result["build_wall_s"] = wall
        if not args.dry_run:
            with open(repo_path(stem + ".stderr.txt"), "w") as f:
                f.write(err)
            with open(repo_path(stem + ".stdout.txt"), "w") as f:
                f.write(out)
    result["build_rc"] = rc
    result["messages"] = mesh_messages(err)
    if rc != 0:
        result["build_error"] = err.strip().splitlines()[-1] if err.strip() else f"exit {rc}"
    s = read_json(repo_path(stats))
    if s is not None:
        result["stats"] = {k: s.get(k) for k in ("eps", "bbox_diagonal", "samples", "sampling", "splats_selected", "output_splats", "total_ms", "phase_ms")}
    if rc != 0 or not os.path.exists(repo_path(ply)):
        return result
    vcmd = [args.splatcl, "splats", "verify", model, ply, "--json", verify_json]
    result["verify_command"] = shlex.join(vcmd)
    if reuse:
        v = read_json(repo_path(verify_json))
        result["verify_rc"] = 0 if (v or {}).get("ok") else 1
        try:
            with open(repo_path(stem + ".verify.txt")) as f:
                result["verify_output"] = f.read()
        except OSError:
            result["verify_output"] = ""
    else:
        vrc, vout, verr, vwall = run(vcmd, load, args.dry_run)
        result["verify_rc"], result["verify_wall_s"] = vrc, vwall
        result["verify_output"] = (vout + "\n".join(l for l in verr.replace("\r", "\n").splitlines() if l.startswith("splatcl:"))).strip()
        if not args.dry_run:
            with open(repo_path(stem + ".verify.txt"), "w") as f:
                f.write(result["verify_output"] + "\n")
    v = read_json(repo_path(verify_json))
    if v is not None:
        result["verify"] = v
    return result


def row(r, eps_label):
    v = r.get("verify")
    s = r.get("stats") or {}
    cells = [f"{r['model']}", r["variant"], eps_label]
    if v is None:
        why = r.get("build_error") or "verify wrote no JSON"
        return "| " + " | ".join(cells + [f"**failed**: {why}"] + [""] * 9) + " |"
    eps = v["eps"]
    sp, su = v["splats"], v["surface"]
    uncovered = 100 * su["uncovered_fraction"]
    hole = su.get("largest_hole_diameter_eps", su["largest_hole_diameter"] / eps if eps else 0)
    ok = v.get("ok") and r.get("verify_rc") == 0
    total = s.get("total_ms")
    check = (s.get("phase_ms") or {}).get("check")
    if total is None:
        time_cell = "–"
    elif check is not None:
        time_cell = f"{total / 1000:.2f} ({check / 1000:.2f})"
    else:
        time_cell = f"{total / 1000:.2f}"
    cells += [
        fmt_count(sp["count"]),
        f"{uncovered:.2f}" if uncovered >= 0.01 or uncovered == 0 else f"{uncovered:.2g}",
        fmt_g(hole),
        fmt_g(sp["max_distance_eps"], 4),
        f"{100 * sp['area_beyond_fraction']:.1f}",
        fmt_count(sp["splats_beyond"]),
        fmt_g(sp["largest_major_diagonal"]),
        fmt_count(sp["flipped"]) + (f" ({sp['degenerate']} degenerate)" if sp.get("degenerate") else ""),
        "ok" if ok else "**fails**",
        time_cell,
    ]
    if r["variant"] == "after":
        cells[3] = f"**{cells[3]}**"  # the splat count of the two-sided variant
    return "| " + " | ".join(cells) + " |"


HEADER = ("| model | variant | ε | splats | uncovered area % | largest hole (diameter / ε) | largest splat-to-surface distance / ε "
          "| splat area beyond ε % | splats beyond ε | largest major semi-axis / diagonal | flipped | verify | build time, s (of which end-of-run check) |\n"
          "|---|---|---|---|---|---|---|---|---|---|---|---|---|")


def cpu_model():
    try:
        out = subprocess.run(["lscpu"], capture_output=True, text=True).stdout
        for line in out.splitlines():
            if line.startswith("Model name:"):
                return line.split(":", 1)[1].strip()
    except OSError:
        pass
    return platform.processor() or "unknown CPU"


def main():
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0], epilog=__doc__.split("\n\n", 1)[1],
                                formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--splatcl", required=True, help="the splatcl binary, e.g. build-table/splatcl")
    p.add_argument("--models", required=True, help="folder of the test models (*.obj), e.g. data/models")
    p.add_argument("--out", required=True, help="folder for the splat files, statistics and verify JSON (created), e.g. out/splats-surface-table")
    p.add_argument("--eps-diag", default="0.001", help="eps as a fraction of the bounding-box diagonal for every model (default 0.001)")
    p.add_argument("--extra-eps", action="append", metavar="MODEL=EPS",
                   help="also run MODEL (file name without .obj) at the absolute eps EPS; repeatable "
                        "(default: stanford-bunny=0.0003, the thesis's Table 3.1 eps)")
    p.add_argument("--only", action="append", metavar="MODEL", help="run only these models (repeatable)")
    p.add_argument("--device", help="passed to splatcl splats --device")
    p.add_argument("--reuse", action="store_true", help="reuse the outputs already in --out instead of running again (for reformatting)")
    p.add_argument("--markdown", metavar="FILE", help="also write the Markdown to FILE")
    p.add_argument("--dry-run", action="store_true", help="print the commands only")
    args = p.parse_args()

    splatcl = repo_path(args.splatcl)
    if not os.access(splatcl, os.X_OK):
        p.error(f"--splatcl {args.splatcl}: not an executable file")
    models_dir = repo_path(args.models)
    if not os.path.isdir(models_dir):
        p.error(f"--models {args.models}: not a folder")
    os.makedirs(repo_path(args.out), exist_ok=True)
    extras = args.extra_eps if args.extra_eps is not None else ["stanford-bunny=0.0003"]
    extra = []
    for item in extras:
        name, sep, eps = item.partition("=")
        if not sep:
            p.error(f"--extra-eps {item}: expected MODEL=EPS")
        extra.append((name, eps))

    models = sorted(f for f in os.listdir(models_dir) if f.endswith(".obj"))
    if args.only:
        models = [m for m in models if os.path.splitext(m)[0] in args.only]
    if not models:
        p.error(f"--models {args.models}: no *.obj files")
    no_check_flag = has_flag(splatcl, "--no-check")

    load = LoadSampler()
    started = datetime.datetime.now()
    cases = []  # (eps label, [before, after])
    for m in models:
        name = os.path.splitext(m)[0]
        model = os.path.join(args.models, m)
        runs = [(f"{args.eps_diag} × diag", ["--eps-diag", args.eps_diag], f"diag{args.eps_diag}")]
        runs += [(eps, ["--eps", eps], f"eps{eps}") for (n, eps) in extra if n == name]
        for label, eps_args, tag in runs:
            pair = [run_case(args, load, model, variant, eps_args, tag, no_check_flag) for variant in ("before", "after")]
            for r in pair:
                v = r.get("verify")
                if v:
                    label_eps = f"{label} = {v['eps']:.4g}" if "diag" in label else label
                    r["eps_label"] = label_eps
            cases.append((label, pair))
    finished = datetime.datetime.now()

    lines = [HEADER]
    failures, messages = [], {}
    for label, pair in cases:
        for r in pair:
            lines.append(row(r, r.get("eps_label", label)))
            if r["variant"] == "after" and not (r.get("build_rc") == 0 and r.get("verify_rc") == 0 and (r.get("verify") or {}).get("ok")):
                failures.append(r)
            for msg in r["messages"]:
                messages.setdefault(r["model"], [])
                if msg not in messages[r["model"]]:
                    messages[r["model"]].append(msg)
    lines.append("")
    lines.append("Mesh warnings printed by `splatcl splats` (stderr):")
    lines.append("")
    for m in models:
        name = os.path.splitext(m)[0]
        msgs = messages.get(name)
        lines.append(f"- {name}: " + ("; ".join(x.replace("splatcl: ", "", 1) for x in msgs) if msgs else "none"))
    lines.append("")
    lines.append(f"Run {started:%Y-%m-%d %H:%M}–{finished:%H:%M} on {cpu_model()}, {os.cpu_count()} cores, "
                 f"load average {load.describe()}.")
    if failures:
        lines.append("")
        lines.append("**FAILURES of the two-sided variant:**")
        for r in failures:
            lines.append(f"- {r['model']} ({r['tag']}): build exit {r.get('build_rc')}, verify exit {r.get('verify_rc')}")
            lines.append("```")
            lines.append(r.get("verify_output") or r.get("build_error") or "")
            lines.append("```")
    text = "\n".join(lines) + "\n"
    sys.stdout.write(text)
    if args.markdown:
        with open(repo_path(args.markdown), "w") as f:
            f.write(text)
    if not args.dry_run:
        with open(repo_path(os.path.join(args.out, "summary.json")), "w") as f:
            json.dump({"started": started.isoformat(), "finished": finished.isoformat(), "cpu": cpu_model(),
                       "cores": os.cpu_count(), "load_average": load.values,
                       "runs": [r for _, pair in cases for r in pair]}, f, indent=2)
            f.write("\n")
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
