"""Writing a simulated session: its files and ``truth.json`` in one folder."""

from tactilecal._atomic import make_folder
from tactilecal._jsonutil import write_json


def write_session(outdir, files, truth):
    """Write a session's files, then ``truth.json``, into ``outdir`` (created if missing).

    Parameters
    ----------
    outdir : str or os.PathLike
        Folder, created if missing.
    files : dict
        ``{role: (file name, write)}``, written in this order; ``write(path)`` writes one
        file atomically.
    truth : dict
        Plain values written as ``truth.json`` (role ``truth``), atomically.

    Returns
    -------
    dict
        Paths written, by role (those of ``files``, then ``truth``).
    """
    outdir = make_folder(outdir)
    paths = {role: outdir / name for role, (name, _) in files.items()}
    for role, (_, write) in files.items():
        write(paths[role])
    paths["truth"] = outdir / "truth.json"
    write_json(paths["truth"], truth)
    return paths
