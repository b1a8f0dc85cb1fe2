// Time-series charts on Debian's dygraphs: times in the plant's zone, a
// unit on every value axis, vertical marks (runs, events) drawn under the
// data, and a zoom callback for charts the server thins per range.
"use strict";

const Charts = (() => {
  const { el } = TC;
  const short = new Intl.DateTimeFormat("en-GB", { timeZone: TC.zone, month: "short", day: "2-digit", hour: "2-digit", minute: "2-digit", hour12: false });
  const day = new Intl.DateTimeFormat("en-GB", { timeZone: TC.zone, month: "short", day: "2-digit" });

  function available() { return typeof Dygraph !== "undefined"; }

  // A box for a chart: the plot, its legend, and a caption.
  function box(id, caption, small) {
    const plot = el("div", { id, class: small ? "chart small" : "chart", role: "img", "aria-label": caption });
    const legend = el("div", { class: "legend", id: id + "-legend" });
    return { node: el("figure", { style: "margin:0 0 1em" }, el("figcaption", {}, caption), plot, legend), plot, legend };
  }

  // Vertical marks [{ms, color, width, label}] under the data.
  function underlay(marks) {
    return (ctx, area, g) => {
      for (const m of marks()) {
        const x = g.toDomXCoord(m.ms);
        if (x < area.x || x > area.x + area.w) continue;
        ctx.strokeStyle = m.color;
        ctx.lineWidth = m.width || 1;
        ctx.beginPath();
        ctx.moveTo(x, area.y);
        ctx.lineTo(x, area.y + area.h);
        ctx.stroke();
        if (m.label) {  // what the line marks, beside its top
          ctx.fillStyle = m.color;
          ctx.font = "11px sans-serif";
          ctx.fillText(m.label, Math.min(x + 3, area.x + area.w - ctx.measureText(m.label).width), area.y + 11);
        }
      }
    };
  }

  // rows: [[Date, v1, v2, ...]]; labels: ["time", "measured", ...]
  function time(target, rows, labels, options) {
    if (!available()) {
      target.plot.replaceChildren(el("div", { class: "error" }, "Charts unavailable: the charting library (libjs-dygraphs) is not installed on the server."));
      return null;
    }
    const span = rows.length > 1 ? rows[rows.length - 1][0] - rows[0][0] : 0;
    const o = Object.assign({
      labels,
      labelsDiv: target.legend,
      legend: "always",
      labelsSeparateLines: false,
      connectSeparatedPoints: true,
      drawPoints: false,
      strokeWidth: 1.2,
      xlabel: "time (" + TC.zone + ")",
      axes: {
        x: {
          valueFormatter: (ms) => TC.time(ms),
          // By the span shown now (zoomed, or a new range), not the one
          // drawn first: hours within a few days, dates beyond.
          axisLabelFormatter: (d, granularity, opts, g) => {
            const r = g && g.xAxisRange ? g.xAxisRange() : [0, span];
            return (r[1] - r[0] > 4 * 86400000 ? day : short).format(d);
          },
          pixelsPerLabel: 90,
        },
        y: { axisLabelWidth: 60 },
      },
    }, options || {});
    return new Dygraph(target.plot, rows.length ? rows : [[new Date(), ...labels.slice(1).map(() => null)]], o);
  }

  return { available, box, underlay, time };
})();
