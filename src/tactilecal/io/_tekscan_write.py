"""Writer for Tekscan I-Scan ASCII exports (the layout :func:`read_tekscan` reads)."""

import numpy as np

from tactilecal._atomic import atomic_path, check_target
from tactilecal._errors import TactilecalError
from tactilecal._units import area_to_mm2, length_to_mm, normalise_unit
from tactilecal.io._header import _UPPER_KEY, parse_header_lines

__all__ = ["write_tekscan"]

_MAX_EXACT_INT = 2.0**53
_LUT_MAX = 100_000
_BLOCK_VALUES = 2_000_000  # values formatted per block (bounds memory to ~100 MB)


def write_tekscan(data, path, *, newline="\n", overwrite=False):
    r"""Write a recording as a Tekscan ASCII export that :func:`read_tekscan` reads back.

    The header is the file's original header (``tekscan_<KEY>`` attributes, verbatim) with
    the keys the data defines brought up to date: ``ROWS``, ``COLS``, ``START_FRAME``,
    ``END_FRAME`` from the array; ``UNITS``, ``SENSOR_TYPE``, ``ROW_SPACING``,
    ``COL_SPACING``, ``SENSEL_AREA``, ``SECONDS_PER_FRAME``, ``NOISE_THRESHOLD``,
    ``SENSITIVITY``, ``SCALE_FACTOR``, ``EXPONENT``, ``SATURATION_PRESSURE``,
    ``CALIBRATION_POINT_n``, ``CALIBRATION_MODE_n`` from the parsed attributes where the
    verbatim text no longer says the same. Each frame line is I-Scan's
    ``Frame N, <time s>,,,,,Raw Sum=,,<sum>`` (the ``Raw Sum`` part only for raw data, the
    time only where finite); ``B`` marks NaN; integral values are written without decimals,
    others as the shortest text that reads back to the same float64.

    Parameters
    ----------
    data : xarray.DataArray
        Dims ``("frame", "row", "col")`` with ``frame`` and ``time`` coordinates
        (``docs/data-model.md``).
    path : str or os.PathLike
        Output file, written atomically.
    newline : {"\n", "\r\n"}, keyword-only
        Line ending (Tekscan software on Windows writes ``"\r\n"``).
    overwrite : bool, keyword-only
        Replace an existing ``path`` (only a Tekscan export; default False: an existing
        ``path`` is an error).

    Raises
    ------
    ValueError
        Wrong dims, missing ``frame`` coordinate, infinite values, frame numbers not
        increasing, a header value that would not read back; ``path`` exists (without
        ``overwrite``, or is no Tekscan export).

    Examples
    --------
    >>> import tempfile, pathlib
    >>> import numpy as np, xarray as xr
    >>> from tactilecal.io import read_tekscan
    >>> data = xr.DataArray(np.array([[[0.0, 3.0], [np.nan, 255.0]]]),
    ...                     dims=("frame", "row", "col"),
    ...                     coords={"frame": [1], "time": ("frame", [0.0])},
    ...                     attrs={"units": "raw", "row_spacing_mm": 1.27,
    ...                            "col_spacing_mm": 1.27})
    >>> out = pathlib.Path(tempfile.mkdtemp()) / "sim.csv"
    >>> write_tekscan(data, out)
    >>> print(out.read_text().split("ASCII_DATA @@")[1])
    <BLANKLINE>
    <BLANKLINE>
    Frame 1, 0,,,,,Raw Sum=,,258
    0,3
    B,255
    @@
    <BLANKLINE>
    >>> bool((read_tekscan(out) == data).sum() == 3)
    True
    """
    if newline not in ("\n", "\r\n"):
        raise TactilecalError(f"newline={newline!r}; expected '\\n' or '\\r\\n'")
    check_target(path, overwrite=overwrite, kind="tekscan")
    values, frames, times = _checked_arrays(data)
    header = "\n".join([*_header_lines(data, frames), "ASCII_DATA @@", ""]) + "\n"
    frame_lines = _frame_lines(data, values, frames, times)
    with atomic_path(path) as tmp, open(tmp, "wb") as out:
        out.write(header.replace("\n", newline).encode("utf-8"))
        step = max(1, _BLOCK_VALUES // max(1, values[0].size))
        for first in range(0, values.shape[0], step):
            block = values[first:first + step]
            text, offsets = _format_rows(block.reshape(-1, block.shape[2]), newline.encode())
            bounds = offsets[::block.shape[1]]
            for k, line in enumerate(frame_lines[first:first + step]):
                lead = b"" if first + k == 0 else newline.encode()
                out.write(lead + (line + newline).encode("utf-8"))
                out.write(text[bounds[k]:bounds[k + 1]])
        out.write(f"@@{newline}".encode())


def _checked_arrays(data):
    if tuple(data.dims) != ("frame", "row", "col"):
        raise TactilecalError(f"write_tekscan: data has dims {tuple(data.dims)}; expected "
                              "('frame', 'row', 'col')")
    if "frame" not in data.coords:
        raise TactilecalError("write_tekscan: data has no 'frame' coordinate; expected the "
                              "frame numbers (docs/data-model.md)")
    if data.sizes["frame"] == 0:
        raise TactilecalError("write_tekscan: data has no frames; expected at least one")
    values = np.ascontiguousarray(data.values, dtype=np.float64)
    if np.isinf(values).any():
        frame = data.frame.values[np.isinf(values).any(axis=(1, 2))][0]
        raise TactilecalError(f"write_tekscan: frame {frame} holds infinite values; expected "
                              "finite numbers or NaN (written as B)")
    frames = np.asarray(data.frame.values)
    if not np.issubdtype(frames.dtype, np.integer) or (np.diff(frames) <= 0).any():
        raise TactilecalError(f"write_tekscan: frame numbers {frames[:5].tolist()}...; expected "
                              "increasing integers")
    times = (np.asarray(data.time.values, dtype=np.float64) if "time" in data.coords
             else np.full(frames.size, np.nan))
    return values, frames, times


def _number(value):
    """Shortest text that reads back to the same float64 (``1`` for 1.0)."""
    return np.format_float_positional(float(value), trim="-")


def _same(text, value, convert):
    """Return True when a verbatim header value still parses to ``value``."""
    try:
        number, unit = text.split(None, 1) if " " in text.strip() else (text, None)
        parsed = convert(float(number), unit.strip()) if unit else float(number)
    except (ValueError, AttributeError):
        return False
    return parsed == value  # the reader made ``value`` from this text the same way


# Key order of Tekscan's own exports (I-Scan 6.10I / F-Scan 6.33 in shared/realdata).
_ORDER = ("DATA_TYPE", "VERSION", "SENSOR_TYPE", "ROWS", "COLS", "ROW_SPACING", "COL_SPACING",
          "SENSEL_AREA", "NOISE_THRESHOLD", "SECONDS_PER_FRAME", "SCALE_FACTOR", "EXPONENT",
          "SATURATION_PRESSURE", "CALIBRATION_POINT_1", "CALIBRATION_POINT_2",
          "CALIBRATION_MODE_1", "CALIBRATION_MODE_2", "SENSITIVITY", "START_FRAME",
          "END_FRAME", "UNITS")


def _ordered(header, verbatim):
    """Keep the file's key order; put each new key after its predecessor in ``_ORDER``."""
    keys = [k for k in header if k in verbatim]
    for key in header:
        if key in verbatim:
            continue
        rank = _ORDER.index(key) if key in _ORDER else len(_ORDER)
        before = [i for i, k in enumerate(keys) if k in _ORDER and _ORDER.index(k) < rank]
        keys.insert(before[-1] + 1 if before else 0, key)
    return {k: header[k] for k in keys}


def _header_lines(data, frames):
    attrs = data.attrs
    header = {k[len("tekscan_"):]: str(v) for k, v in attrs.items() if k.startswith("tekscan_")}
    verbatim = set(header)
    header.setdefault("DATA_TYPE", "MOVIE")  # the only DATA_TYPE seen in real exports
    managed = {
        "SENSOR_TYPE": attrs.get("sensor_type"),
        "ROWS": str(data.sizes["row"]), "COLS": str(data.sizes["col"]),
        "SENSITIVITY": attrs.get("sensitivity"),
        "START_FRAME": str(frames[0]) if frames.size else None,
        "END_FRAME": str(frames[-1]) if frames.size else None,
    }
    for key, value in managed.items():
        if value is not None:
            header[key] = str(value)
    for key, attr, convert, unit in (
            ("ROW_SPACING", "row_spacing_mm", length_to_mm, "mm"),
            ("COL_SPACING", "col_spacing_mm", length_to_mm, "mm"),
            ("SENSEL_AREA", "sensel_area_mm2", area_to_mm2, "mm2"),
            ("SECONDS_PER_FRAME", "seconds_per_frame", None, ""),
            ("NOISE_THRESHOLD", "noise_threshold", None, ""),
            ("SCALE_FACTOR", "scale_factor", None, ""),
            ("EXPONENT", "exponent", None, "")):
        if attr in attrs and not _same(header.get(key, ""), attrs[attr], convert):
            header[key] = f"{_number(attrs[attr])} {unit}".strip()
    _calibration_header(attrs, header)
    if "units" in attrs:
        current = header.get("UNITS")
        try:
            keep = current is not None and normalise_unit(current) == attrs["units"]
        except ValueError:
            keep = False
        if not keep:
            header["UNITS"] = str(attrs["units"])
    return _render_header(_ordered(header, verbatim))


def _calibration_header(attrs, header):
    """Compose calibration keys from parsed attributes where the verbatim text is absent."""
    if "saturation_pressure" in attrs and "SATURATION_PRESSURE" not in header:
        unit = attrs.get("saturation_pressure_unit", "")
        header["SATURATION_PRESSURE"] = f"{_number(attrs['saturation_pressure'])} {unit}".strip()
    for key in attrs:
        if key.startswith("calibration_mode_"):
            header.setdefault(f"CALIBRATION_MODE_{key.rsplit('_', 1)[1]}", str(attrs[key]))
        if key.startswith("calibration_point_") and key.endswith("_raw_sum"):
            prefix = key[:-len("raw_sum")]
            n = prefix.split("_")[2]
            text = (f"{_number(attrs[prefix + 'load'])} ({attrs[prefix + 'load_unit']}) "
                    f"{_number(attrs[key])} (Raw Sum)")
            if prefix + "loaded_cells" in attrs:
                text += f" {attrs[prefix + 'loaded_cells']} (Number of Loaded Cells)"
            header.setdefault(f"CALIBRATION_POINT_{n}", text)


def _render_header(header):
    lines = []
    for key, value in header.items():
        if key == "COMMENTS" or "\n" in value:
            comment = value.splitlines()
            if key != "COMMENTS" or any(_UPPER_KEY.match(c.strip()) for c in comment):
                raise TactilecalError(f"write_tekscan: header value {key}={value[:40]!r} would not "
                                      "read back; expected a single line (COMMENTS: lines not "
                                      "starting with an upper-case KEY)")
            lines.append(f"{key}:")
            lines.extend(comment)
        else:
            lines.append(f"{key} {value}".rstrip())
    parse_header_lines(lines, "the header being written")  # fail now, not when reading
    return lines


def _frame_lines(data, values, frames, times):
    raw = data.attrs.get("units") == "raw"
    sums = np.nansum(values, axis=(1, 2)) if raw else None
    lines = []
    for k, frame in enumerate(frames.tolist()):
        line = f"Frame {frame}"
        if np.isfinite(times[k]):
            line += f", {_number(times[k])}"
            if raw:
                line += f",,,,,Raw Sum=,,{_number(sums[k])}"
        lines.append(line)
    return lines


def _tokens(table):
    """Text of each value as a fixed-width bytes array and each text's length."""
    finite = np.isfinite(table)
    integral = finite & (table == np.round(table)) & (np.abs(table) < _MAX_EXACT_INT)
    ints = np.where(integral, table, 0).astype(np.int64)
    low, high = (int(ints.min()), int(ints.max())) if ints.size else (0, 0)
    rest = finite & ~integral
    if high - low <= _LUT_MAX:  # raw readings: look the text up, no conversion per value
        lut = np.array([str(v).encode() for v in range(low, high + 1)] + [b"B"])
        index = np.where(finite, ints - low, high - low + 1)
        tokens, lengths = lut[index], np.char.str_len(lut)[index]
    else:
        tokens = np.where(finite, ints.astype(bytes), b"B")
        lengths = None
    if rest.any():  # shortest text that reads back to the same float64 (numpy's repr)
        floats = table[rest].astype(bytes)
        tokens = tokens.astype(f"S{max(tokens.dtype.itemsize, floats.dtype.itemsize)}")
        tokens[rest] = floats
        lengths = None
    return tokens, np.char.str_len(tokens) if lengths is None else lengths


def _format_rows(table, newline):
    """Text of ``table`` as comma-separated lines and the byte offset where each line starts.

    ``B`` stands for NaN, integers are written without decimals. Returns ``(bytes, offsets)``
    with ``offsets`` of length ``n_rows + 1``.

    Vectorised: every value's text is padded to a fixed width, a separator byte is put
    after each, and a mask keeps the text bytes and the separators in order.
    """
    tokens, lengths = _tokens(table)
    tokens = np.ascontiguousarray(tokens)
    n_rows, n_cols = table.shape
    width = tokens.dtype.itemsize
    chars = np.zeros((n_rows, n_cols, width + len(newline)), dtype=np.uint8)
    chars[:, :, :width] = tokens.view(np.uint8).reshape(n_rows, n_cols, width)
    chars[:, :-1, width] = ord(",")
    chars[:, -1, width:] = np.frombuffer(newline, np.uint8)
    keep = np.arange(width + len(newline)) < lengths[:, :, None]
    keep[:, :-1, width] = True
    keep[:, -1, width:] = True
    line_bytes = lengths.sum(axis=1) + (n_cols - 1) + len(newline)
    return chars[keep].tobytes(), np.concatenate(([0], np.cumsum(line_bytes)))
