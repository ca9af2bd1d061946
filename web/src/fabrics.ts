// The fabric cache: every cached fabric with its name (from the precompute jobs that
// made it), method, size, use and pin; pin, unpin and remove.
import { call, listJobs, type CachedFabric } from "./api.js";
import { h, replaceChildren } from "./dom.js";
import { bytes, time } from "./format.js";
import type { PageView } from "./page.js";
import { poll } from "./poll.js";

// A fabric's manifest never changes under its key: read once a page.
export interface Manifest {
  method?: string;
  resolution?: number;
  fitted_levels?: number;
  fit_seconds?: number;
  settings?: Record<string, unknown>;
  levels?: Record<string, unknown>[];
}

export async function manifestOf(key: string): Promise<Manifest> {
  const reply = await call<{ manifestJson?: string }>("GetFabric", { fabricKey: key });
  return JSON.parse(reply.manifestJson || "{}") as Manifest;
}

export async function fabricNames(): Promise<Map<string, string>> {
  const names = new Map<string, string>();
  for (const job of (await listJobs([], ["JOB_KIND_PRECOMPUTE"])).jobs) {
    if (job.fabricKey && job.name) names.set(job.fabricKey, job.name);
  }
  return names;
}

export const fabricsPage: PageView = ({ root, onError }) => {
  const summary = h("p", { id: "cache-summary", class: "summary" });
  const body = h("tbody");
  replaceChildren(
    root,
    h("h1", {}, "Fabrics"),
    summary,
    h(
      "table",
      { id: "fabrics", class: "grid" },
      h(
        "thead",
        {},
        h(
          "tr",
          {},
          ...["key", "name", "method", "size", "created", "last used", "pinned", ""].map((c) => h("th", {}, c)),
        ),
      ),
      body,
    ),
  );
  const manifests = new Map<string, Promise<Manifest>>();
  const refresh = async () => {
    const [list, names] = await Promise.all([
      call<{ fabrics?: CachedFabric[]; totalBytes: string; budgetBytes: string }>("ListFabrics"),
      fabricNames(),
    ]);
    const fabrics = list.fabrics ?? [];
    const methods = await Promise.all(
      fabrics.map((f) => {
        if (!manifests.has(f.fabricKey))
          manifests.set(
            f.fabricKey,
            manifestOf(f.fabricKey).catch(() => ({})),
          );
        return manifests.get(f.fabricKey)!;
      }),
    );
    const again = () => void refresh().catch(onError);
    body.replaceChildren(
      ...fabrics.map((fabric, i) => {
        const row = h(
          "tr",
          {},
          h("td", {}, h("a", { href: `#/fabrics/${fabric.fabricKey}` }, h("code", {}, fabric.fabricKey.slice(0, 16)))),
          h("td", {}, names.get(fabric.fabricKey) ?? ""),
          h("td", {}, methods[i].method ?? ""),
          h("td", {}, bytes(fabric.totalBytes)),
          h("td", {}, time(fabric.createdMs)),
          h("td", {}, time(fabric.lastUsedMs)),
          h("td", {}, fabric.pinned ? "pinned" : ""),
          h(
            "td",
            {},
            h(
              "button",
              {
                class: "pin",
                onclick: () =>
                  call("PinFabric", { fabricKey: fabric.fabricKey, pinned: !fabric.pinned }).then(again, onError),
              },
              fabric.pinned ? "Unpin" : "Pin",
            ),
            h(
              "button",
              {
                class: "remove",
                onclick: () => {
                  if (confirm(`Remove fabric ${fabric.fabricKey.slice(0, 16)} from the cache?`)) {
                    call("DeleteFabric", { fabricKey: fabric.fabricKey }).then(again, onError);
                  }
                },
              },
              "Remove",
            ),
          ),
        );
        row.dataset.fabric = fabric.fabricKey;
        return row;
      }),
    );
    const budget = Number(list.budgetBytes) ? ` of ${bytes(list.budgetBytes)}` : " (no budget)";
    summary.textContent = `${fabrics.length} fabric(s) · store ${bytes(list.totalBytes)}${budget}`;
  };
  return poll(refresh, 5000, onError);
};
