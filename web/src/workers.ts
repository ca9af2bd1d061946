// The workers page: the server's queue depth, cache use and uptime, and every
// worker this server process knows with its GL renderer, state, job and counts.
import { call, type ServerInfo, type WorkerInfo } from "./api.js";
import { h, replaceChildren } from "./dom.js";
import { bytes, duration, time } from "./format.js";
import { REFRESH_MS, type PageView } from "./page.js";
import { poll } from "./poll.js";

export const workersPage: PageView = ({ root, onError }) => {
  const server = h("dl", { id: "server", class: "details" });
  const body = h("tbody");
  replaceChildren(
    root,
    h("h1", {}, "Workers"),
    server,
    h(
      "table",
      { id: "workers", class: "grid" },
      h(
        "thead",
        {},
        h(
          "tr",
          {},
          ...["worker", "host", "GL renderer", "state", "job", "last heard", "succeeded", "failed"].map((c) =>
            h("th", {}, c),
          ),
        ),
      ),
      body,
    ),
  );
  const refresh = async () => {
    const [info, workers, cache] = await Promise.all([
      call<ServerInfo>("GetServerInfo"),
      call<{ workers?: WorkerInfo[] }>("ListWorkers"),
      call<{ totalBytes: string; budgetBytes: string }>("ListFabrics"),
    ]);
    const budget = Number(cache.budgetBytes) ? bytes(cache.budgetBytes) : "no budget";
    const facts: [string, string][] = [
      ["version", info.version],
      ["health", info.health],
      ["queued", info.queuedJobs],
      ["running", info.runningJobs],
      ["cache", `${bytes(cache.totalBytes)} of ${budget}`],
      ["fabrics", info.cachedFabrics],
      ["uptime", duration(Number(info.uptimeMs))],
      ["TLS", info.tls ? "yes" : "no"],
    ];
    replaceChildren(server, ...facts.flatMap(([k, v]) => [h("dt", {}, k), h("dd", { "data-fact": k }, v)]));
    body.replaceChildren(
      ...(workers.workers ?? []).map((w) => {
        const row = h(
          "tr",
          {},
          h("td", {}, h("code", {}, w.workerId)),
          h("td", {}, w.capabilities?.hostname ?? ""),
          h("td", {}, `${w.capabilities?.glRenderer ?? ""}${w.capabilities?.softwareGl ? " (software)" : ""}`),
          h("td", {}, h("span", { class: `state worker-${w.state}` }, w.state)),
          h("td", {}, w.currentJobId ? h("a", { href: `#/jobs/${w.currentJobId}` }, w.currentJobId) : ""),
          h("td", {}, time(w.lastSeenMs)),
          h("td", {}, String(w.jobsSucceeded ?? 0)),
          h("td", {}, String(w.jobsFailed ?? 0)),
        );
        row.dataset.worker = w.workerId;
        return row;
      }),
    );
  };
  return poll(refresh, REFRESH_MS, onError);
};
