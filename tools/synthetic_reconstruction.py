"""Shared by the reconstruction benchmarks: their common options and one call of
`acq reconstruct synthetic` on a card seen through the seed's 20 directions."""
import os
import re
import subprocess
import sys

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
SEED_DIRECTIONS = os.path.join(ROOT, "data", "directions", "seed_directions_20.tsv")


def add_common_options(ap, size):
    ap.add_argument("--size", type=int, default=size)
    ap.add_argument("--build", default=os.path.join(ROOT, "build"))
    ap.add_argument("--basis", default=os.path.join(ROOT, "out", "main", "basis90.acqb"))
    ap.add_argument("--out", default=os.path.join(ROOT, "out", "bench", "reconstruction"))


def acq_from(a):
    """The acq binary; exits with a message when the basis is not there."""
    os.makedirs(a.out, exist_ok=True)
    if not os.path.exists(a.basis):
        sys.exit(f"bench: no basis at {a.basis}: run tools/run-main.sh first (or give --basis)")
    return os.path.join(a.build, "src", "cli", "acq")


def reconstruct(acq, basis, size, fov, out_map, extra=(), threads=None):
    """Runs the reconstruction (table ground truth); returns (solve seconds, stdout)."""
    env = dict(os.environ)
    if threads:
        env["OMP_NUM_THREADS"] = str(threads)
    res = subprocess.run([acq, "reconstruct", "synthetic", "--basis", basis, "--directions",
                          SEED_DIRECTIONS, "--size", f"{size}x{size}", "--fov-deg", str(fov),
                          "--truth-tables", "--quiet", "-o", out_map, *extra],
                         capture_output=True, text=True, env=env)
    if res.returncode:
        sys.exit(res.stdout + res.stderr)
    return float(re.search(r"time: ([\d.]+) s solving", res.stdout).group(1)), res.stdout
