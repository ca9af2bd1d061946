// A fabric's page: its preview on a sphere (core/render/fabric_preview.h), its
// manifest's settings, the fit's figures and pictures of its texels per level
// (core/methods/asset_pictures.h) and its files.
import { artifactUrl, call, type ArtifactRef, type CachedFabric } from "./api.js";
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

// An entry of pictures.json, written by the worker beside the asset.
interface TexelPicture {
  file: string;
  level: number;
  map: string;
  caption: string;
}

async function texelPictures(files: ArtifactRef[]): Promise<TexelPicture[]> {
  const list = files.find((file) => file.name === "pictures.json");
  if (!list) return [];
  const reply = await fetch(artifactUrl(list.sha256), { credentials: "same-origin" });
  if (!reply.ok) throw new Error(`pictures.json: HTTP ${reply.status}`);
  return (await reply.json()) as TexelPicture[];
}

// A row per level, a column per map, each picture one pixel per texel scaled up
// without smoothing; the captions below say what each map shows.
function picturesTable(pictures: TexelPicture[], files: ArtifactRef[]): HTMLElement {
  if (pictures.length === 0) return h("p", {}, "No texel pictures (made by workers since they came).");
  const maps = [...new Set(pictures.map((p) => p.map))];
  const levels = [...new Set(pictures.map((p) => p.level))].sort((a, b) => a - b);
  const sha = new Map(files.map((file) => [file.name, file.sha256]));
  const cell = (level: number, map: string) => {
    const picture = pictures.find((p) => p.level === level && p.map === map);
    const hash = picture && sha.get(picture.file);
    return h(
      "td",
      {},
      hash
        ? h("img", { class: "texels", src: artifactUrl(hash), alt: `level ${level} ${map}`, title: picture.caption })
        : "",
    );
  };
  const captions = new Map(pictures.map((p) => [p.map, p.caption]));
  return h(
    "div",
    { id: "texels" },
    h(
      "table",
      { class: "grid narrow" },
      h("thead", {}, h("tr", {}, h("th", {}, "level"), ...maps.map((map) => h("th", {}, map)))),
      h(
        "tbody",
        {},
        ...levels.map((level) => h("tr", {}, h("th", {}, String(level)), ...maps.map((m) => cell(level, m)))),
      ),
    ),
    h("dl", { class: "details" }, ...maps.flatMap((map) => [h("dt", {}, map), h("dd", {}, captions.get(map) ?? "")])),
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
    const files = entry?.files ?? [];
    const preview = files.find((file) => file.name === "preview.png");
    const pictures = await texelPictures(files);
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
      h("h2", {}, "Texels per level"),
      picturesTable(pictures, files),
      h("h2", {}, "Files"),
      h(
        "ul",
        { class: "files" },
        ...files.map((file) =>
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
