"""Where the pounding kernel spends its time: a sampling profile by function.

``python -m benchmarks.profile_kernel [--model M | --row BxS] [--physics NAME] [--seconds S] [--lines N] [--keep DIR]``
(Linux, needs ``perf`` and ``nm`` on the PATH).

numba's compiled code has no symbols that ``perf`` can see, so this does it in
three steps:

1. a child process compiles the kernel into a fresh, temporary numba cache, so
   that the object code of the compiled library is at hand, and writes that
   object file; a second child loads the same object from that cache, writes the
   address at which ``integrate_kernel`` was loaded, and runs ``integrate`` on
   the model in a loop;
2. ``perf record`` samples the child (only while it loops, not while it compiles);
3. each sampled instruction address, less the load address, is an offset into the
   object's code section, and ``nm`` gives every function's offset and size there
   (numba emits its helpers as weak symbols; those it inlines into the kernel
   count as the kernel's own lines).

Printed: the share of the samples in each function of the kernel's library, and
the share of the process's samples outside it by shared object (BLAS for the
free-flight products, Python for ``integrate``'s own overhead).  Shares of
samples, not times: the loop runs ``integrate`` back to back, so they are shares
of a run.
"""

from __future__ import annotations

import argparse
import bisect
import collections
import os
import re
import shutil
import signal
import subprocess
import sys
import tempfile
import time
from pathlib import Path

REPO = Path(__file__).resolve().parent.parent


def _child(model: str, row: str | None, out: Path, seconds: float, physics: str | None = None,
           driver: str = "auto") -> int:
    from seispound import load_model
    from seispound.integrate import _driver as D
    from seispound.integrate import integrate
    from seispound.simulation import newmark_substeps, prepare_ground_motion, run_inputs
    from seispound.structure import assemble

    if row:  # a row of the scaling benchmark: B buildings of S storeys, 20 s of El Centro
        from .scaling import _ground, _row

        nb, ns = (int(x) for x in row.lower().split("x"))
        system = _row(nb, ns)
        dt = 0.005
        ag, nsteps = _ground(20.0, dt)

        def run():
            return integrate(system, ag, dt, nsteps, driver=driver)
    elif physics and "/" in physics:  # a diagnose form on the speed benchmark's case (name/form)
        m = _diagnose_form(physics, out)
        an = m.analysis
        system, motions = run_inputs(m)
        n_nm = newmark_substeps(m, system)

        def run():
            return integrate(system, motions.rows, an.dt, an.nsteps, an.newmark, substeps=n_nm, driver=driver)
    elif physics:  # a case of benchmarks.physics (its driver's kernel is profiled)
        from .physics import cases

        m = cases(load_model(model))[physics]
        an = m.analysis
        system, motions = run_inputs(m)
        n_nm = newmark_substeps(m, system)

        def run():
            return integrate(system, motions.rows, an.dt, an.nsteps, an.newmark, substeps=n_nm, driver=driver)
    else:
        m = load_model(model)
        an = m.analysis
        system = assemble(m.buildings, m.gaps, m.contact)
        ag, _ = prepare_ground_motion(m)

        def run():
            return integrate(system, ag, an.dt, an.nsteps, an.newmark, driver=driver)

    raw = run()
    kernel = D.general_kernel if raw.driver == "general" else D.integrate_kernel
    cres = next(iter(kernel.overloads.values()))
    lib = cres.library
    if not (out / "kernel.o").exists():
        # first child: compiled into the fresh cache, so the object code is at hand; stop here
        # (a library compiled in this process is laid out apart from its object file)
        (out / "kernel.o").write_bytes(lib._get_compiled_object())
        return 0
    # second child: loaded that object from the cache, where the offsets of kernel.o hold
    addr = lib.get_pointer_to_function(cres.fndesc.mangled_name)
    (out / "kernel_addr").write_text(f"{addr:x}\n")
    (out / "stats").write_text(repr(raw.stats))
    for _ in range(3):
        run()
    print("ready", flush=True)
    sys.stdin.readline()  # the parent starts perf, then says go
    t0 = time.perf_counter()
    n = 0
    while time.perf_counter() - t0 < seconds:
        run()
        n += 1
    print(f"runs {n} {(time.perf_counter() - t0) / n:.6f}", flush=True)
    return 0


def _diagnose_form(name: str, out: Path):
    """The model of ``diagnose``'s form ``hypothesis/form`` (e.g. distributed-mass/_attached) at its null
    point, on the case of ``benchmarks.diagnose.speed --forms`` (two buildings, 30 s at 200 Hz)."""
    import tomllib

    from seispound.calibrate.api import load_inputs
    from seispound.calibrate.observe import Observer
    from seispound.diagnose.hypotheses import ALTERNATIVES, HYPOTHESES

    from .diagnose.generate import write_case

    hyp_name, form_name = name.split("/")
    f = out / "case"
    if not (f / "model.toml").exists():
        write_case(f, "none", 31, duration=30.0, buildings=2)
    model, chans, trials = load_inputs(f / "model.toml", [f / "recording.mseed"], f / "channels.toml", None)
    data = tomllib.loads(model.text)
    data.setdefault("analysis", {}).setdefault("contact_substeps", 32)
    hyp = {**HYPOTHESES, **ALTERNATIVES}[hyp_name]
    k = [fn.__name__ for fn in hyp.forms].index(form_name)
    table, _, null = hyp.augment(data, k)
    return Observer(table, f, chans, trials).model_for(trials[0], list(null.items()))


def _symbols(obj: Path):
    """(offset, size, name) of the functions in the object's code, sorted by offset."""
    txt = subprocess.run(["nm", "-S", str(obj)], capture_output=True, text=True, check=True).stdout
    syms = []
    for line in txt.splitlines():
        p = line.split()
        if len(p) == 4 and p[2] in "TtWw":
            # readable name: the module and function of the mangled path (_ZN9seispound9integrate7_kernel...)
            m = re.match(r"^(cfunc\.)?_ZN(.*)", p[3])
            name = p[3]
            if m:
                parts, rest = [], m.group(2)
                while rest[:1].isdigit():
                    k = re.match(r"\d+", rest).group(0)
                    parts.append(rest[len(k):len(k) + int(k)])
                    rest = rest[len(k) + int(k):]
                name = (m.group(1) or "") + ".".join(parts[-2:])
            syms.append((int(p[0], 16), int(p[1], 16), name))
    return sorted(syms)


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(prog="python -m benchmarks.profile_kernel", description=__doc__.split("\n\n")[0])
    ap.add_argument("--model", default=str(REPO / "models" / "row_of_three.toml"))
    ap.add_argument("--row", help="instead of a model: a row of the scaling benchmark, e.g. 4x25 "
                    "(buildings x storeys, 20 s of El Centro 180, Hd, gaps 2 cm)")
    ap.add_argument("--physics", help="instead of the model as it is: a case of benchmarks.physics on it, e.g. "
                    "'flexible foundation' (the general driver's kernel when it runs there); or a form of "
                    "diagnose on the case of benchmarks.diagnose.speed, e.g. 'distributed-mass/_attached'")
    ap.add_argument("--driver", default="auto", choices=("auto", "fast", "general"),
                    help="the driver to run (default auto: the one integrate picks)")
    ap.add_argument("--seconds", type=float, default=10.0, help="length of the sampled loop (default 10)")
    ap.add_argument("--frequency", type=int, default=10000, help="perf sampling frequency [Hz]")
    ap.add_argument("--lines", type=int, default=0, metavar="N",
                    help="also the N source lines with most samples; numba inlines in its own IR, so an "
                    "inlined helper's samples fall on the helper's lines (compiles with NUMBA_DEBUGINFO=1; "
                    "needs addr2line; the general driver's debug build, every phase inlined, grew past 24 GB of "
                    "memory and was killed)")
    ap.add_argument("--keep", metavar="DIR",
                    help="keep the compiled kernel (and numba's cache) in DIR, and reuse them when DIR holds them: "
                         "another model on the same driver is then profiled without compiling again (a kernel "
                         "kept from another source, or with --lines where it had none, is compiled again)")
    ap.add_argument("--child", help=argparse.SUPPRESS)
    args = ap.parse_args(argv)
    if args.child:
        return _child(args.model, args.row, Path(args.child), args.seconds, args.physics, args.driver)
    for tool in ("perf", "nm"):
        if shutil.which(tool) is None:
            print(f"benchmarks.profile_kernel: {tool} not found on the PATH", file=sys.stderr)
            return 2
    with tempfile.TemporaryDirectory(prefix="seispound-profile-") as tmp:
        out = Path(args.keep) if args.keep else Path(tmp)
        out.mkdir(parents=True, exist_ok=True)
        for old in ("kernel_addr", "stats", "perf.data"):  # a kept folder's last profile
            (out / old).unlink(missing_ok=True)
        # a kept kernel serves only the source and build it was compiled from: its offsets are the cache's
        from seispound._jit import package_stamp

        key = f"{package_stamp()} lines={bool(args.lines)}\n"
        if (out / "kernel.o").exists() and (not (out / "key").exists() or (out / "key").read_text() != key):
            print("benchmarks.profile_kernel: the kept kernel was compiled from another source or build: "
                  "compiling again", file=sys.stderr)
            shutil.rmtree(out / "numba-cache", ignore_errors=True)
            (out / "kernel.o").unlink()
        env = dict(os.environ, NUMBA_CACHE_DIR=str(out / "numba-cache"))
        if args.lines:
            env["NUMBA_DEBUGINFO"] = "1"
        cmd = [sys.executable, "-m", "benchmarks.profile_kernel", "--model", args.model,
               "--seconds", str(args.seconds), "--driver", args.driver, "--child", str(out)]
        cmd += (["--row", args.row] if args.row else []) + (["--physics", args.physics] if args.physics else [])
        if not (out / "kernel.o").exists():
            print("compiling the kernel into a fresh numba cache (minutes; with --lines tens of minutes) ...",
                  file=sys.stderr, flush=True)
            if subprocess.run(cmd, cwd=REPO, env=env).returncode != 0 or not (out / "kernel.o").exists():
                print("benchmarks.profile_kernel: compiling the kernel failed", file=sys.stderr)
                return 2
            (out / "key").write_text(key)
        child = subprocess.Popen(cmd,
                                 cwd=REPO, env=env, stdin=subprocess.PIPE, stdout=subprocess.PIPE, text=True)
        line = child.stdout.readline()
        if line.strip() != "ready":
            child.wait()
            print("benchmarks.profile_kernel: the child did not start", file=sys.stderr)
            return 2
        data = out / "perf.data"
        perf = subprocess.Popen(["perf", "record", "-q", "-F", str(args.frequency), "-o", str(data),
                                 "-p", str(child.pid)], stderr=subprocess.PIPE, text=True)
        time.sleep(0.5)  # perf attached
        child.stdin.write("go\n")
        child.stdin.flush()
        runs = child.stdout.readline().split()
        child.wait()
        perf.send_signal(signal.SIGINT)
        _, err = perf.communicate()
        if perf.returncode not in (0, -signal.SIGINT) or not data.exists():
            last = err.strip().splitlines()[-1] if err.strip() else f"exit code {perf.returncode}"
            print(f"benchmarks.profile_kernel: perf record failed: {last}", file=sys.stderr)
            return 2
        script = subprocess.run(["perf", "script", "-i", str(data), "-F", "ip,dso"],
                                capture_output=True, text=True).stdout
        base = int((out / "kernel_addr").read_text(), 16)
        syms = _symbols(out / "kernel.o")
        stats = (out / "stats").read_text()
        offsets = collections.Counter()
        for line in script.splitlines():
            p = line.split()
            try:
                offsets[int(p[0], 16) - base] += 1
            except (ValueError, IndexError):
                continue
        lines = _source_lines(out / "kernel.o", offsets, syms) if args.lines else None
    starts = [s for s, _, _ in syms]
    inside = collections.Counter()
    outside = collections.Counter()
    total = 0
    for line in script.splitlines():
        p = line.split()
        if not p:
            continue
        try:
            ip = int(p[0], 16)
        except ValueError:
            continue
        total += 1
        off = ip - base
        k = bisect.bisect_right(starts, off) - 1
        if k >= 0 and off < syms[k][0] + syms[k][1]:
            inside[syms[k][2]] += 1
        else:
            dso = p[1].strip("()") if len(p) > 1 else "?"
            outside[Path(dso).name if dso.startswith("/") else dso] += 1
    n_in = sum(inside.values())
    what = f"row {args.row}" if args.row else f"model {args.model}" + (f", {args.physics}" if args.physics else "")
    print(f"{what}: {runs[1]} runs of integrate() back to back, {float(runs[2]) * 1e3:.2f} ms each; "
          f"{total} samples at {args.frequency} Hz")
    print(f"stats of one run: {stats}")
    print(f"\nthe kernel's library: {100 * n_in / total:.1f} % of the samples; by function "
          f"(share of the library's samples; helpers inlined into the kernel count as integrate_kernel):")
    for name, c in inside.most_common():
        if c / n_in >= 0.001:
            print(f"  {100 * c / n_in:5.1f} %  {name}")
    print("\noutside it (share of all samples), by shared object:")
    for name, c in outside.most_common(8):
        print(f"  {100 * c / total:5.1f} %  {name}")
    if lines:
        print(f"\nthe {args.lines} source lines with most of the library's samples ('?': no line recorded):")
        for where, c in lines.most_common(args.lines):
            print(f"  {100 * c / n_in:5.1f} %  {where}")
    return 0


def _source_lines(obj: Path, offsets, syms):
    """Samples per source line of the offsets inside the object's functions, through addr2line on its
    debug information (``NUMBA_DEBUGINFO=1``)."""
    starts = [s for s, _, _ in syms]
    inside = [off for off in offsets
              if (k := bisect.bisect_right(starts, off) - 1) >= 0 and off < syms[k][0] + syms[k][1]]
    txt = subprocess.run(["addr2line", "-e", str(obj), "-a"] + [f"{off:x}" for off in inside],
                         capture_output=True, text=True).stdout.splitlines()
    out = collections.Counter()
    for addr, where in zip(txt[0::2], txt[1::2]):  # -a: the address, then its file:line
        out[re.sub(r".*/seispound/", "", where.split(" (")[0])] += offsets[int(addr, 16)]
    return out


if __name__ == "__main__":
    raise SystemExit(main())
