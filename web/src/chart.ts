// The speed-versus-accuracy chart of a committed sweep (docs/results/*.csv, copied
// into the dashboard when it is built): a point per configuration at its median
// frame time and median PSNR over the sweep's scenes; hovering shows its figures.
import { h, replaceChildren } from "./dom.js";
import type { PageView } from "./page.js";

const SWEEPS = ["sweep.csv", "methods.csv", "volume.csv"];
const SVG = "http://www.w3.org/2000/svg";
const COLOURS = ["#1f77b4", "#d62728", "#2ca02c", "#9467bd", "#ff7f0e", "#8c564b", "#e377c2", "#17becf", "#7f7f7f"];

export function parseCsv(text: string): Record<string, string>[] {
  const rows: string[][] = [];
  let row: string[] = [];
  let field = "";
  let quoted = false;
  for (let i = 0; i < text.length; ++i) {
    const c = text[i];
    if (quoted) {
      if (c === '"' && text[i + 1] === '"') {
        field += '"';
        ++i;
      } else if (c === '"') {
        quoted = false;
      } else {
        field += c;
      }
    } else if (c === '"') {
      quoted = true;
    } else if (c === ",") {
      row.push(field);
      field = "";
    } else if (c === "\n") {
      row.push(field);
      rows.push(row);
      row = [];
      field = "";
    } else if (c !== "\r") {
      field += c;
    }
  }
  if (field || row.length) rows.push([...row, field]);
  const [header, ...data] = rows;
  return data.map((r) => Object.fromEntries(header.map((name, i) => [name, r[i] ?? ""])));
}

function median(values: number[]): number {
  const sorted = values.filter(Number.isFinite).sort((a, b) => a - b);
  if (!sorted.length) return NaN;
  const mid = sorted.length >> 1;
  return sorted.length % 2 ? sorted[mid] : (sorted[mid - 1] + sorted[mid]) / 2;
}

export interface Point {
  configuration: string;
  method: string;
  scenes: number;
  psnr: number;
  perceptual: number;
  frameMs: number;
  precomputeS: number;
}

export function configurationPoints(rows: Record<string, string>[]): Point[] {
  const groups = new Map<string, Record<string, string>[]>();
  for (const row of rows) {
    const list = groups.get(row.configuration) ?? [];
    list.push(row);
    groups.set(row.configuration, list);
  }
  const number = (list: Record<string, string>[], column: string) => median(list.map((r) => parseFloat(r[column])));
  return [...groups.entries()]
    .map(([configuration, list]) => ({
      configuration,
      method: list[0].method,
      scenes: list.length,
      psnr: number(list, "psnr_db"),
      perceptual: number(list, "perceptual_error"),
      frameMs: number(list, "frame_ms"),
      precomputeS: number(list, "precompute_seconds"),
    }))
    .filter((p) => p.frameMs > 0 && Number.isFinite(p.psnr));
}

function svg<K extends keyof SVGElementTagNameMap>(
  tag: K,
  attributes: Record<string, string | number>,
): SVGElementTagNameMap[K] {
  const element = document.createElementNS(SVG, tag);
  for (const [name, value] of Object.entries(attributes)) element.setAttribute(name, String(value));
  return element;
}

function plot(points: Point[], tooltip: HTMLElement): SVGSVGElement {
  const width = 860,
    height = 480,
    left = 60,
    right = 30,
    top = 20,
    bottom = 50;
  const xs = points.map((p) => Math.log10(p.frameMs));
  const ys = points.map((p) => p.psnr);
  const [x0, x1] = [Math.floor(Math.min(...xs)), Math.ceil(Math.max(...xs))];
  const [y0, y1] = [Math.floor(Math.min(...ys) - 1), Math.ceil(Math.max(...ys) + 1)];
  const sx = (v: number) => left + ((v - x0) / Math.max(x1 - x0, 1e-9)) * (width - left - right);
  const sy = (v: number) => top + (1 - (v - y0) / Math.max(y1 - y0, 1e-9)) * (height - top - bottom);
  const chart = svg("svg", { id: "chart", viewBox: `0 0 ${width} ${height}`, role: "img" });
  chart.append(
    svg("rect", { x: left, y: top, width: width - left - right, height: height - top - bottom, class: "plot" }),
  );
  for (let e = x0; e <= x1; ++e) {
    const tick = svg("text", { x: sx(e), y: height - bottom + 18, "text-anchor": "middle", class: "tick" });
    tick.textContent = e >= 3 ? `${10 ** (e - 3)} s` : `${10 ** e} ms`;
    chart.append(svg("line", { x1: sx(e), x2: sx(e), y1: top, y2: height - bottom, class: "gridline" }), tick);
  }
  for (let v = y0; v <= y1; v += Math.max(1, Math.round((y1 - y0) / 8))) {
    const tick = svg("text", { x: left - 8, y: sy(v) + 4, "text-anchor": "end", class: "tick" });
    tick.textContent = `${v}`;
    chart.append(svg("line", { x1: left, x2: width - right, y1: sy(v), y2: sy(v), class: "gridline" }), tick);
  }
  const xLabel = svg("text", { x: (left + width) / 2, y: height - 8, "text-anchor": "middle", class: "axis" });
  xLabel.textContent = "frame time (median over scenes, log)";
  const yLabel = svg("text", {
    x: 14,
    y: height / 2,
    transform: `rotate(-90 14 ${height / 2})`,
    "text-anchor": "middle",
    class: "axis",
  });
  yLabel.textContent = "PSNR dB (median over scenes)";
  chart.append(xLabel, yLabel);
  const methods = [...new Set(points.map((p) => p.method))];
  for (const point of points) {
    const dot = svg("circle", {
      cx: sx(Math.log10(point.frameMs)),
      cy: sy(point.psnr),
      r: 6,
      fill: COLOURS[methods.indexOf(point.method) % COLOURS.length],
      class: "point",
      "data-configuration": point.configuration,
    });
    dot.addEventListener("mouseenter", (event) => {
      tooltip.replaceChildren(
        h("strong", {}, point.configuration),
        h("br"),
        `method ${point.method} · ${point.scenes} scene(s)`,
        h("br"),
        `PSNR ${point.psnr.toFixed(2)} dB · perceptual ${point.perceptual.toFixed(4)}`,
        h("br"),
        `frame ${point.frameMs.toFixed(1)} ms · precompute ${point.precomputeS.toFixed(1)} s`,
      );
      tooltip.hidden = false;
      tooltip.style.left = `${(event as MouseEvent).pageX + 12}px`;
      tooltip.style.top = `${(event as MouseEvent).pageY + 12}px`;
    });
    dot.addEventListener("mouseleave", () => (tooltip.hidden = true));
    chart.append(dot);
  }
  methods.forEach((method, i) => {
    const y = top + 14 + i * 18;
    const label = svg("text", { x: width - right - 110, y: y + 4, class: "legend" });
    label.textContent = method;
    chart.append(svg("circle", { cx: width - right - 122, cy: y, r: 5, fill: COLOURS[i % COLOURS.length] }), label);
  });
  return chart;
}

export const chartPage: PageView = ({ root, onError }) => {
  const choice = h(
    "select",
    { id: "sweep", "aria-label": "sweep" },
    ...SWEEPS.map((s) => h("option", { value: s }, s)),
  );
  const tooltip = h("div", { id: "tooltip", class: "tooltip", hidden: true });
  const holder = h("div", { class: "chart" });
  replaceChildren(
    root,
    h("h1", {}, "Speed and accuracy"),
    h("p", {}, "The committed sweep results (docs/results; docs/accuracy.md says how they were made). ", choice),
    holder,
    tooltip,
  );
  const load = async () => {
    const response = await fetch(`results/${choice.value}`);
    if (!response.ok) throw new Error(`results/${choice.value}: ${response.status}`);
    replaceChildren(holder, plot(configurationPoints(parseCsv(await response.text())), tooltip));
  };
  choice.addEventListener("change", () => load().catch(onError));
  load().catch(onError);
  return () => tooltip.remove();
};
