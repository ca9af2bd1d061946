// The jobs page: every job, live, filtered by state and kind, with cancel, retry and
// priority in each row. A poll lists the jobs only when one changed since the last
// (ListJobs' version), and rebuilds only the rows whose job changed.
import { listJobs, type Job, type ServerInfo, call } from "./api.js";
import { h, replaceChildren } from "./dom.js";
import { enumLabel, shortId, time } from "./format.js";
import { actionButtons, priorityInput, updatePriorityInput } from "./job_actions.js";
import { REFRESH_MS, type PageView } from "./page.js";
import { poll } from "./poll.js";

const STATES = ["QUEUED", "LEASED", "RUNNING", "SUCCEEDED", "FAILED", "CANCELLED"];
const KINDS = ["PRECOMPUTE", "RENDER", "ANIMATE"];

export function stateBadge(state: string): HTMLElement {
  const label = enumLabel(state, "JOB_STATE_");
  return h("span", { class: `state state-${label}` }, label);
}

export function progressBar(job: Job): HTMLElement {
  const fraction = Math.max(0, Math.min(1, job.progress?.fraction ?? 0));
  const bar = h("div", { class: "bar" });
  bar.style.width = `${(fraction * 100).toFixed(1)}%`;
  return h(
    "div",
    { class: "progress", title: job.progress?.stage ?? "" },
    h("div", { class: "track" }, bar),
    h("span", { class: "stage" }, `${Math.round(fraction * 100)}% ${job.progress?.stage ?? ""}`),
  );
}

function select(id: string, values: string[], label: string): HTMLSelectElement {
  return h(
    "select",
    { id, "aria-label": label },
    h("option", { value: "" }, `every ${label}`),
    ...values.map((v) => h("option", { value: v }, v.toLowerCase())),
  );
}

export const jobsPage: PageView = ({ root, onError }) => {
  const stateFilter = select("state-filter", STATES, "state");
  const kindFilter = select("kind-filter", KINDS, "kind");
  const summary = h("p", { id: "jobs-summary", class: "summary" });
  const body = h("tbody");
  const table = h(
    "table",
    { id: "jobs", class: "grid" },
    h(
      "thead",
      {},
      h(
        "tr",
        {},
        ...[
          "job",
          "name",
          "kind",
          "state",
          "priority",
          "progress",
          "attempts",
          "worker",
          "submitted",
          "started",
          "finished",
          "",
        ].map((c) => h("th", {}, c)),
      ),
    ),
    body,
  );
  replaceChildren(root, h("h1", {}, "Jobs"), h("div", { class: "filters" }, stateFilter, kindFilter), summary, table);

  let version = "";
  const rows = new Map<string, { row: HTMLTableRowElement; key: string; priority: HTMLInputElement }>();
  const refresh = async () => {
    const states = stateFilter.value ? [`JOB_STATE_${stateFilter.value}`] : [];
    const kinds = kindFilter.value ? [`JOB_KIND_${kindFilter.value}`] : [];
    const [list, info] = await Promise.all([listJobs(states, kinds, version), call<ServerInfo>("GetServerInfo")]);
    if (!list.unchanged) {
      version = list.version;
      updateRows(list.jobs);
    }
    summary.textContent =
      `${rows.size} job(s) shown · queued ${info.queuedJobs} · running ${info.runningJobs} · ` +
      `workers ${info.registeredWorkers} · ${info.health}`;
  };
  const updateRows = (jobs: Job[]) => {
    const seen = new Set<string>();
    const ordered: HTMLTableRowElement[] = [];
    for (const job of jobs) {
      seen.add(job.id);
      const key = JSON.stringify(job);
      let entry = rows.get(job.id);
      if (!entry) {
        const priority = priorityInput(job, () => void refresh().catch(onError), onError);
        entry = { row: h("tr"), key: "", priority };
        entry.row.dataset.job = job.id;
        rows.set(job.id, entry);
      }
      if (entry.key !== key) {
        entry.key = key;
        updatePriorityInput(entry.priority, job);
        replaceChildren(
          entry.row,
          h("td", {}, h("a", { href: `#/jobs/${job.id}`, class: "job-link" }, shortId(job.id))),
          h("td", { class: "name" }, job.name ?? ""),
          h("td", {}, enumLabel(job.kind, "JOB_KIND_")),
          h("td", { class: "state-cell" }, stateBadge(job.state)),
          h("td", {}, entry.priority),
          h("td", {}, progressBar(job)),
          h("td", {}, `${job.attempts ?? 0}/${job.maxAttempts ?? 0}`),
          h("td", {}, job.workerId ?? ""),
          h("td", {}, time(job.timings?.submittedMs)),
          h("td", {}, time(job.timings?.startedMs)),
          h("td", {}, time(job.timings?.finishedMs)),
          h(
            "td",
            {},
            actionButtons(job, () => void refresh().catch(onError), onError),
          ),
        );
      }
      ordered.push(entry.row);
    }
    for (const id of [...rows.keys()]) if (!seen.has(id)) rows.delete(id);
    if (ordered.length !== body.children.length || ordered.some((row, i) => body.children[i] !== row)) {
      body.replaceChildren(...ordered);
    }
  };
  let stop = poll(refresh, REFRESH_MS, onError);
  const restart = () => {
    stop();
    version = "";
    rows.clear();
    body.replaceChildren();
    stop = poll(refresh, REFRESH_MS, onError);
  };
  stateFilter.addEventListener("change", restart);
  kindFilter.addEventListener("change", restart);
  return () => stop();
};
