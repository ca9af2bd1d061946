// What the jobs table and a job's page can do to a job: cancel, retry, reprioritise.
import { call, ENDED_STATES, type Job } from "./api.js";
import { h } from "./dom.js";

export function cancelJob(job: Job): Promise<Job> {
  return call<Job>("CancelJob", { jobId: job.id });
}

export function retryJob(job: Job): Promise<unknown> {
  return call("RetryJobs", { jobIds: [job.id] });
}

export function setPriority(job: Job, priority: number): Promise<Job> {
  return call<Job>("SetJobPriority", { jobId: job.id, priority });
}

// The priority field: Enter or leaving it sets the priority; it is not overwritten
// while it has the focus.
export function priorityInput(job: Job, onDone: () => void, onError: (error: unknown) => void): HTMLInputElement {
  const input = h("input", {
    class: "priority",
    type: "number",
    step: 1,
    value: job.priority ?? 0,
    title: "Higher runs first (Enter to set)",
  });
  input.dataset.job = job.id;
  const commit = () => {
    const value = Number(input.value);
    if (
      !Number.isInteger(value) ||
      value === (input.dataset.priority ? Number(input.dataset.priority) : job.priority)
    ) {
      return;
    }
    setPriority(job, value).then(onDone, onError);
  };
  input.addEventListener("change", commit);
  input.addEventListener("keydown", (event) => {
    if (event.key === "Enter") input.blur();
  });
  return input;
}

export function updatePriorityInput(input: HTMLInputElement, job: Job): void {
  input.dataset.priority = String(job.priority ?? 0);
  input.disabled = ENDED_STATES.includes(job.state);
  if (document.activeElement !== input) input.value = String(job.priority ?? 0);
}

export function actionButtons(job: Job, onDone: () => void, onError: (error: unknown) => void): HTMLElement {
  const ended = ENDED_STATES.includes(job.state);
  const span = h("span", { class: "actions" });
  if (!ended && !job.cancelRequested) {
    span.append(h("button", { class: "cancel", onclick: () => cancelJob(job).then(onDone, onError) }, "Cancel"));
  }
  if (job.state === "JOB_STATE_FAILED" || job.state === "JOB_STATE_CANCELLED") {
    span.append(h("button", { class: "retry", onclick: () => retryJob(job).then(onDone, onError) }, "Retry"));
  }
  return span;
}
