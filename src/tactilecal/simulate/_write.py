"""Writing a simulated session: its files and ``truth.json`` in one folder."""

from tactilecal._atomic import OUTPUT_FOLDERS, check_folder, make_folder
from tactilecal._jsonutil import write_json


def check_session_folder(outdir, overwrite):
    """Raise unless ``outdir`` is new, empty, or (``overwrite``) an earlier session's folder."""
    check_folder(outdir, overwrite=overwrite, **OUTPUT_FOLDERS["session"])


def write_session(outdir, files, truth, *, overwrite=False):
    """Write a session's files, then ``truth.json``, into ``outdir`` (created if missing).

    Parameters
    ----------
    outdir : str or os.PathLike
        Folder, created if missing.
    files : dict
        ``{role: (file name, write)}``, written in this order; ``write(path)`` writes one
        file atomically (replacing it).
    truth : dict
        Plain values written as ``truth.json`` (role ``truth``), atomically.
    overwrite : bool, keyword-only
        Write into a folder that holds files: only an earlier session's (default False).

    Returns
    -------
    dict
        Paths written, by role (those of ``files``, then ``truth``).
    """
    check_session_folder(outdir, overwrite)
    outdir = make_folder(outdir)
    paths = {role: outdir / name for role, (name, _) in files.items()}
    for role, (_, write) in files.items():
        write(paths[role])
    paths["truth"] = outdir / "truth.json"
    write_json(paths["truth"], truth)
    return paths
