"""Runs softplc scenario files as Ray tasks and merges their results.

Each task runs `softplc test --jsonl --shard I/N FILES...` (one shard of the
files, ranked by path and dealt round-robin), the driver gathers the JSON
lines, writes them to --out (or, without it, to a temporary file it removes
afterwards) and sums them with `softplc test --merge`, whose summary it
prints; the exit status is softplc's (0 when every assertion passed).

    python3 examples/scale/ray_suite.py --workers 2 examples/sim/*.toml

Without --address, Ray starts a one-node local cluster with --workers CPUs;
with --address (e.g. `auto` after `ray start --head`) it joins that cluster,
whose nodes must have the softplc binary and the scenario files at the same
paths. See examples/scale/README.md.
"""
import argparse
import os
import pathlib
import subprocess
import sys
import tempfile
import time

import ray


@ray.remote(num_cpus=1)
def run_shard(softplc: str, index: int, count: int, files: list, cwd: str) -> str:
    """One shard, on one CPU: its JSON lines (stdout of softplc test)."""
    out = subprocess.run(
        [softplc, "test", "--jsonl", "--no-progress", "--jobs", "1",
         "--shard", f"{index}/{count}", *files],
        capture_output=True, text=True, cwd=cwd,
    )
    # 0: all passed, 1: some assertion failed; anything else is a usage or
    # system error, which fails the task.
    if out.returncode not in (0, 1):
        raise RuntimeError(f"shard {index}/{count}: exit {out.returncode}: {out.stderr}")
    return out.stdout


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("files", nargs="+", help="scenario files")
    ap.add_argument("--workers", type=int, default=os.cpu_count() or 1,
                    help="CPUs of the local cluster (without --address)")
    ap.add_argument("--shards", type=int, default=None,
                    help="tasks (default: one per file, so Ray balances them)")
    ap.add_argument("--address", default=None, help="an existing Ray cluster, e.g. auto")
    ap.add_argument("--softplc", default=os.environ.get("SOFTPLC", "softplc"),
                    help="the softplc binary (default: $SOFTPLC, else softplc on PATH)")
    ap.add_argument("--out", default=None,
                    help="keep the gathered JSON lines in this file (default: a temporary file, removed)")
    args = ap.parse_args(argv)

    shards = args.shards or len(args.files)
    if args.address:
        ray.init(address=args.address, log_to_driver=False)
    else:
        ray.init(num_cpus=args.workers, include_dashboard=False, log_to_driver=False)
    try:
        start = time.monotonic()
        cwd = os.getcwd()
        tasks = [run_shard.remote(args.softplc, i, shards, args.files, cwd) for i in range(shards)]
        lines = [line for text in ray.get(tasks) for line in text.splitlines() if line.strip()]
        wall = time.monotonic() - start
    finally:
        ray.shutdown()
    with tempfile.TemporaryDirectory(prefix="softplc-ray-") as tmp:
        out = pathlib.Path(args.out or pathlib.Path(tmp) / "results.jsonl")
        out.write_text("".join(line + "\n" for line in lines))
        merged = subprocess.run([args.softplc, "test", "--merge", str(out)], capture_output=True, text=True)
    sys.stdout.write(merged.stdout)
    sys.stderr.write(merged.stderr)
    print(f"{len(lines)} scenario files in {shards} shards on Ray: {wall:.2f} s wall "
          f"(workers: {args.workers if not args.address else args.address})", file=sys.stderr)
    return merged.returncode


if __name__ == "__main__":
    sys.exit(main())
