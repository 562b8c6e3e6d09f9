"""A frame player in the page: a slider over the frames, the map, the force with a cursor.

Self-contained: the frames are in the page as base64 bytes (each sensel's pressure as one of
255 colour levels on the recording's scale, 255 for a blank sensel), drawn into a
``<canvas>`` by a few lines of JavaScript with the viridis colour map; nothing is fetched.
Long recordings are decimated (every k-th frame) so that the frames take at most
:data:`PLAYER_MAX_BYTES`; the force trace keeps every frame.
"""

import base64
import html
import json

import numpy as np

from tactilecal._model import positive_attr
from tactilecal._text import number

__all__ = ["PLAYER_MAX_BYTES", "PLAYER_MAX_FRAMES", "player_html", "PLAYER_SCRIPT"]

PLAYER_MAX_BYTES = 1_500_000
"""Bytes of frame data one player holds at most (2 MB once base64-encoded)."""

PLAYER_MAX_FRAMES = 2000
"""Frames one player shows at most (every k-th frame of longer recordings)."""

_TRACE_W, _TRACE_H = 640, 150
_BLANK = 255


def _viridis():
    from matplotlib import colormaps

    rgb = (colormaps["viridis"](np.linspace(0, 1, 255))[:, :3] * 255).round().astype(np.uint8)
    return base64.b64encode(rgb.tobytes()).decode("ascii")


def _shown(n_frames, cells):
    """Frame positions shown: every k-th, within the byte and frame budgets.

    Examples
    --------
    >>> _shown(10_000, 44 * 44)[:3].tolist(), len(_shown(10_000, 44 * 44))
    ([0, 13, 26], 770)
    """
    budget = max(1, min(PLAYER_MAX_FRAMES, PLAYER_MAX_BYTES // max(cells, 1)))
    return np.arange(0, n_frames, max(1, int(np.ceil(n_frames / budget))))


def player_html(recording, label, *, summary, units_label, factor, key):
    """Return the HTML of one frame player.

    Parameters
    ----------
    recording : xarray.DataArray
        The recording in kPa (calibrated), or raw readings.
    label : str
        Its name in the page.
    summary : xarray.Dataset
        Its ``frame_summary()`` (force and centre of force of every frame), or for a raw
        recording a Dataset with ``force_N`` holding the raw sums.
    units_label : str
        The unit shown (``"kPa"``, ``"raw reading"``...).
    factor : float
        Values are divided by it for display (kPa per unit shown).
    key : str
        Unique id of the player in the page.
    """
    values = np.asarray(recording.values, dtype=float) / factor
    n, rows, cols = values.shape
    shown = _shown(n, rows * cols)
    top = float(np.nanmax(values)) if np.isfinite(values).any() else 0.0
    levels = np.where(np.isnan(values[shown]), _BLANK,
                      np.clip(np.rint(np.nan_to_num(values[shown]) / (top or 1.0) * 254), 0, 254)
                      ).astype(np.uint8)
    mask, _ = recording.tactile.saturation_mask()
    saturated = None if mask is None else np.asarray(mask.values)[shown]
    t = np.asarray(summary["time"].values if "time" in summary.coords else np.arange(n), float)
    force = np.asarray(summary["force_N"].values, float)
    row_mm, col_mm = (positive_attr(recording, k) for k in ("row_spacing_mm", "col_spacing_mm"))
    data = {
        "rows": rows, "cols": cols, "rowMm": row_mm, "colMm": col_mm, "top": top,
        "unit": units_label, "label": label, "frames": np.asarray(
            recording["frame"].values if "frame" in recording.coords else np.arange(1, n + 1)
        )[shown].tolist(),
        "shown": shown.tolist(), "t": [round(float(v), 6) for v in t],
        "force": [None if not np.isfinite(v) else float(number(v)) for v in force],
        "forceLabel": "total force [N]" if units_label != "raw reading" else
        "sum of raw readings",
        "cof": _centres(summary, shown),
        "levels": base64.b64encode(levels.tobytes()).decode("ascii"),
        "saturated": None if saturated is None or not saturated.any() else
        base64.b64encode(np.packbits(saturated.reshape(len(shown), -1), axis=1).tobytes())
        .decode("ascii"),
        "cmap": _viridis(),
    }
    start = int(np.argmin(np.abs(shown - int(np.nanargmax(np.nan_to_num(force, nan=-1))))))
    payload = json.dumps(data, separators=(",", ":")).replace("</", "<\\/")
    step = shown[1] - shown[0] if len(shown) > 1 else 1
    note = (f"every {step}th of {n} frames shown" if step > 1 else f"all {n} frames shown")
    return (f'<div class="player" id="{key}"><div class="player-row">'
            f'<canvas class="map" aria-label="pressure map of {html.escape(label)}"></canvas>'
            f'<div class="legend"></div>'
            f'<svg class="trace" viewBox="0 0 {_TRACE_W} {_TRACE_H}" '
            f'preserveAspectRatio="none"></svg></div>'
            f'<input class="slider" type="range" min="0" max="{len(shown) - 1}" '
            f'value="{start}" aria-label="frame">'
            f'<span class="frame-label"></span> <span class="player-note">({note})</span>'
            f'<script type="application/json" class="player-data">{payload}</script></div>')


def _centres(summary, shown):
    if "cof_row_mm" not in summary:
        return None
    rows = np.asarray(summary["cof_row_mm"].values, float)[shown]
    cols = np.asarray(summary["cof_col_mm"].values, float)[shown]
    return [[round(float(r), 3), round(float(c), 3)] if np.isfinite(r) and np.isfinite(c)
            else None for r, c in zip(rows, cols, strict=True)]


PLAYER_SCRIPT = """<script>
(function () {
  function bytes(text) {
    const raw = atob(text), out = new Uint8Array(raw.length);
    for (let i = 0; i < raw.length; i++) out[i] = raw.charCodeAt(i);
    return out;
  }
  function setUp(box) {
    const d = JSON.parse(box.querySelector(".player-data").textContent);
    const levels = bytes(d.levels), cmap = bytes(d.cmap);
    const sat = d.saturated ? bytes(d.saturated) : null;
    const cells = d.rows * d.cols, satBytes = Math.ceil(cells / 8);
    const canvas = box.querySelector("canvas.map"), ctx = canvas.getContext("2d");
    const scale = Math.max(2, Math.floor(Math.min(320 / (d.cols * d.colMm),
                                                  420 / (d.rows * d.rowMm)) * 4) / 4);
    const cw = d.colMm * scale, ch = d.rowMm * scale;
    canvas.width = Math.round(d.cols * cw); canvas.height = Math.round(d.rows * ch);
    const legend = box.querySelector(".legend");
    const stops = [0, 64, 127, 191, 254].map(
      k => `rgb(${cmap[3 * k]},${cmap[3 * k + 1]},${cmap[3 * k + 2]}) ${k / 2.54}%`);
    legend.innerHTML = `<div class="bar" style="background:linear-gradient(to top,` +
      `${stops.join(",")})"></div><span class="top">${d.top.toPrecision(4)} ${d.unit}</span>` +
      `<span class="bottom">0</span>`;
    const svg = box.querySelector("svg.trace"), W = __W__, H = __H__, NS = svg.namespaceURI;
    const t0 = d.t[0], t1 = d.t[d.t.length - 1] || 1;
    const fmax = Math.max(...d.force.filter(v => v !== null), 1e-12);
    const x = t => 40 + (W - 50) * (t - t0) / ((t1 - t0) || 1);
    const y = f => H - 20 - (H - 35) * f / fmax;
    const pts = d.force.map((f, i) => f === null ? null : `${x(d.t[i]).toFixed(1)},` +
                            `${y(f).toFixed(1)}`).filter(p => p).join(" ");
    svg.innerHTML = `<polyline class="force" fill="none" stroke="#1f77b4" ` +
      `stroke-width="1.2" points="${pts}"/>` +
      `<line class="axis" x1="40" y1="${H - 20}" x2="${W - 10}" y2="${H - 20}" ` +
      `stroke="#888"/><text x="40" y="12" font-size="11">${d.forceLabel}, ` +
      `max ${fmax.toPrecision(4)}</text><text x="40" y="${H - 4}" font-size="11">` +
      `${t0.toFixed(3)} s</text><text x="${W - 10}" y="${H - 4}" font-size="11" ` +
      `text-anchor="end">${t1.toFixed(3)} s</text>` +
      `<line class="cursor" x1="0" y1="15" x2="0" y2="${H - 20}" stroke="#d62728" ` +
      `stroke-width="2"/>`;
    const cursor = svg.querySelector("line.cursor");
    const text = box.querySelector(".frame-label"), slider = box.querySelector(".slider");
    function draw(k) {
      const image = ctx.createImageData(canvas.width, canvas.height), px = image.data;
      for (let r = 0; r < d.rows; r++) {
        const y0 = Math.round(r * ch), y1 = Math.round((r + 1) * ch);
        for (let c = 0; c < d.cols; c++) {
          const v = levels[k * cells + r * d.cols + c];
          const x0 = Math.round(c * cw), x1 = Math.round((c + 1) * cw);
          for (let yy = y0; yy < y1; yy++) for (let xx = x0; xx < x1; xx++) {
            const p = 4 * (yy * canvas.width + xx);
            if (v === 255) { px[p] = px[p + 1] = px[p + 2] = 255; }
            else { px[p] = cmap[3 * v]; px[p + 1] = cmap[3 * v + 1]; px[p + 2] = cmap[3 * v + 2]; }
            px[p + 3] = 255;
          }
        }
      }
      ctx.putImageData(image, 0, 0);
      if (sat) {
        ctx.strokeStyle = "red"; ctx.lineWidth = 1.5;
        for (let i = 0; i < cells; i++) {
          if (sat[k * satBytes + (i >> 3)] & (128 >> (i & 7))) {
            const cx = ((i % d.cols) + 0.5) * cw, cy = (Math.floor(i / d.cols) + 0.5) * ch;
            const s = Math.min(cw, ch) * 0.35;
            ctx.beginPath(); ctx.moveTo(cx - s, cy - s); ctx.lineTo(cx + s, cy + s);
            ctx.moveTo(cx + s, cy - s); ctx.lineTo(cx - s, cy + s); ctx.stroke();
          }
        }
      }
      const cof = d.cof ? d.cof[k] : null;
      if (cof) {
        const cx = (cof[1] / d.colMm + 0.5) * cw, cy = (cof[0] / d.rowMm + 0.5) * ch;
        ctx.fillStyle = "white"; ctx.strokeStyle = "black"; ctx.lineWidth = 1;
        ctx.beginPath(); ctx.arc(cx, cy, 4, 0, 2 * Math.PI); ctx.fill(); ctx.stroke();
      }
      const i = d.shown[k], xc = x(d.t[i]).toFixed(1);
      cursor.setAttribute("x1", xc); cursor.setAttribute("x2", xc);
      const f = d.force[i] === null ? "n/a" : d.force[i].toPrecision(4);
      text.textContent = `frame ${d.frames[k]}, t = ${d.t[i].toFixed(3)} s, ` +
        `${d.forceLabel.split(" [")[0]} = ${f}${d.forceLabel.includes("[N]") ? " N" : ""}`;
      box.dataset.frame = String(d.frames[k]);
    }
    slider.addEventListener("input", () => draw(Number(slider.value)));
    draw(Number(slider.value));
  }
  document.querySelectorAll("div.player").forEach(setUp);
})();
</script>""".replace("__W__", str(_TRACE_W)).replace("__H__", str(_TRACE_H))
