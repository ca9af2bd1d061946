// A job's page: its state and times, its fabric and dependencies, its actions, its
// live log and its frames.
import { artifactUrl, call, ENDED_STATES, type Job } from "./api.js";
import { h, replaceChildren } from "./dom.js";
import { duration, enumLabel, time } from "./format.js";
import { actionButtons, priorityInput, updatePriorityInput } from "./job_actions.js";
import { progressBar, stateBadge } from "./jobs.js";
import { REFRESH_MS, type PageView } from "./page.js";
import { poll } from "./poll.js";

function frame(sha256: string): HTMLElement {
  const link = h("a", { href: artifactUrl(sha256), download: sha256 }, `download ${sha256.slice(0, 12)}`);
  const image = h("img", { class: "frame", src: artifactUrl(sha256), alt: `result ${sha256.slice(0, 12)}` });
  // EXR frames and glTF sequences are not images a browser shows: a link then.
  image.addEventListener("error", () => image.replaceWith(h("span", { class: "not-an-image" }, "not a PNG")));
  return h("figure", {}, image, h("figcaption", {}, link));
}

export const jobPage: PageView = ({ root, argument: id, onError }) => {
  const details = h("dl", { class: "details" });
  const actions = h("div", { class: "job-actions" });
  const frames = h("div", { id: "frames", class: "frames" });
  const log = h("pre", { id: "log", class: "log" });
  replaceChildren(
    root,
    h("h1", {}, "Job ", h("code", {}, id)),
    actions,
    details,
    h("h2", {}, "Results"),
    frames,
    h("h2", {}, "Log"),
    log,
  );

  let shownFrames = "";
  let ended = false;
  let priority: HTMLInputElement | undefined;
  const refresh = async () => {
    if (ended) return;
    const [job, logReply] = await Promise.all([
      call<Job>("GetJob", { jobId: id }),
      call<{ lines?: string[] }>("GetJobLog", { jobId: id }),
    ]);
    const again = () => void refresh().catch(onError);
    priority ??= priorityInput(job, again, onError);
    updatePriorityInput(priority, job);
    replaceChildren(actions, h("label", {}, "priority ", priority), actionButtons(job, again, onError));
    const rows: [string, Node | string][] = [
      ["state", stateBadge(job.state)],
      ["kind", enumLabel(job.kind, "JOB_KIND_")],
      ["progress", progressBar(job)],
      ["attempts", `${job.attempts ?? 0} of ${job.maxAttempts ?? 0}`],
      ["worker", job.workerId ?? ""],
      ["submitted", time(job.timings?.submittedMs)],
      ["started", time(job.timings?.startedMs)],
      ["finished", time(job.timings?.finishedMs)],
      ["run time", duration(job.timings?.runMs ?? 0)],
    ];
    if (job.name) rows.push(["name", job.name]);
    const fabricLink = (key: string) => h("a", { class: "fabric-key", href: `#/fabrics/${key}` }, key);
    if (job.fabricKey) rows.push(["fabric", fabricLink(job.fabricKey)]);
    if (job.fabricKeys?.length) {
      rows.push(["fabrics", h("span", { class: "keys" }, ...job.fabricKeys.map(fabricLink))]);
    }
    if (job.dependsOn?.length) {
      rows.push(["depends on", h("span", {}, ...job.dependsOn.map((d) => h("a", { href: `#/jobs/${d}` }, `${d} `)))]);
    }
    if (job.error) rows.push(["error", h("span", { class: "error" }, job.error)]);
    replaceChildren(details, ...rows.flatMap(([name, value]) => [h("dt", {}, name), h("dd", {}, value)]));
    const results = (job.resultArtifacts ?? []).join(",");
    if (results !== shownFrames) {
      shownFrames = results;
      replaceChildren(frames, ...(job.resultArtifacts ?? []).map(frame));
    }
    log.textContent = (logReply.lines ?? []).join("\n");
    // An ended job changes no more (a retry starts it again: reload to follow).
    ended = ENDED_STATES.includes(job.state);
  };
  return poll(refresh, REFRESH_MS, onError);
};
