"""``persistri``: the command-line entry point; each sub-command lives in its own module."""

from __future__ import annotations

import warnings

import click

from persistri.impl.cli.bench import bench
from persistri.impl.cli.conformance import conformance
from persistri.impl.cli.demo import demo
from persistri.impl.cli.errors import PersistriGroup
from persistri.impl.cli.hull import hull
from persistri.impl.cli.mesh import mesh
from persistri.impl.cli.terrain import terrain
from persistri.impl.cli.delaunay import delaunay_command
from persistri.impl.cli.experiments import experiments

__all__ = ["main"]


@click.group(cls=PersistriGroup, context_settings={"help_option_names": ["-h", "--help"]})
@click.version_option(package_name="persistri")
def main() -> None:
    """persistri: persistent triangulations (Blelloch et al.), typed and checked.

    Every failure (a bad input file, an output that cannot be written, a failed
    check) is one line on stderr naming the file, and exit status 2; files are
    checked before any computation and outputs appear only when all are written.
    An output's directory must exist, except its last level, which is created.
    """
    # numpy warns on reading a .npy written by Python 2 (its header needs more parsing), naming its own source
    # line: the file is read correctly, and the warning's two lines would break the one-line contract.
    warnings.filterwarnings("ignore", message="Reading `.npy` or `.npz` file required additional header parsing")


main.add_command(conformance)
main.add_command(bench)
main.add_command(demo)
main.add_command(hull)
main.add_command(terrain)
main.add_command(delaunay_command)
main.add_command(experiments)
main.add_command(mesh)
