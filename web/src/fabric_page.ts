// A fabric's page: its preview on a sphere (core/render/fabric_preview.h), its
// manifest's settings, the fit's figures per level and its files.
import { artifactUrl, call, type CachedFabric } from "./api.js";
import { h, replaceChildren } from "./dom.js";
import { bytes } from "./format.js";
import { manifestOf } from "./fabrics.js";
import type { PageView } from "./page.js";

function keyValueTable(id: string, values: Record<string, unknown>): HTMLElement {
  return h(
    "table",
    { id, class: "grid narrow" },
    h("tbody", {}, ...Object.entries(values).map(([k, v]) => h("tr", {}, h("th", {}, k), h("td", {}, String(v))))),
  );
}

function levelsTable(levels: Record<string, unknown>[]): HTMLElement {
  const columns = [...new Set(levels.flatMap((level) => Object.keys(level)))];
  const cell = (value: unknown) =>
    typeof value === "number" && !Number.isInteger(value) ? value.toPrecision(4) : String(value ?? "");
  return h(
    "table",
    { id: "levels", class: "grid" },
    h("thead", {}, h("tr", {}, ...columns.map((c) => h("th", {}, c.replaceAll("_", " "))))),
    h("tbody", {}, ...levels.map((level) => h("tr", {}, ...columns.map((c) => h("td", {}, cell(level[c])))))),
  );
}

export const fabricPage: PageView = ({ root, argument: key, onError }) => {
  replaceChildren(root, h("h1", {}, "Fabric ", h("code", {}, key)));
  const load = async () => {
    const [manifest, list] = await Promise.all([manifestOf(key), call<{ fabrics?: CachedFabric[] }>("ListFabrics")]);
    const entry = (list.fabrics ?? []).find((f) => f.fabricKey === key);
    const summary: Record<string, unknown> = {
      method: manifest.method ?? "",
      "texels per tile": manifest.resolution ?? "",
      "fitted levels": manifest.fitted_levels ?? "",
      "fit seconds": manifest.fit_seconds?.toFixed(1) ?? "",
      size: bytes(entry?.totalBytes),
      pinned: entry?.pinned ?? false,
    };
    const preview = entry?.files.find((file) => file.name === "preview.png");
    root.append(
      h(
        "div",
        { class: "fabric-head" },
        preview
          ? h("img", { id: "preview", src: artifactUrl(preview.sha256), alt: "the fabric on a sphere" })
          : h("p", {}, "No preview (made by workers since the dashboard came)."),
        keyValueTable("summary", summary),
      ),
      h("h2", {}, "Settings"),
      keyValueTable("settings", manifest.settings ?? {}),
      h("h2", {}, "Fit per level"),
      levelsTable(manifest.levels ?? []),
      h("h2", {}, "Files"),
      h(
        "ul",
        { class: "files" },
        ...(entry?.files ?? []).map((file) =>
          h(
            "li",
            {},
            h("a", { href: artifactUrl(file.sha256), download: file.name }, file.name),
            ` ${bytes(file.size)}`,
          ),
        ),
      ),
    );
  };
  load().catch(onError);
  return () => {};
};
