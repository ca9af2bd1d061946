// The dashboard's one way to the server: LoomService calls as JSON
// (server/http_gateway.h), the token travelling in the login cookie.

export class ApiError extends Error {
  constructor(
    readonly status: number,
    readonly code: string,
    message: string,
  ) {
    super(message);
  }
}

// Proto3 JSON: int64 fields arrive as strings, enums as their names.
export interface JobProgress {
  fraction?: number;
  stage?: string;
}
export interface JobTimings {
  submittedMs?: string;
  startedMs?: string;
  finishedMs?: string;
  runMs?: number;
}
export interface Job {
  id: string;
  name: string;
  kind: string;
  state: string;
  priority: number;
  attempts: number;
  maxAttempts: number;
  progress?: JobProgress;
  timings?: JobTimings;
  resultArtifacts: string[];
  error: string;
  dependsOn: string[];
  fabricKey: string;
  fabricKeys?: string[];
  workerId: string;
  cancelRequested: boolean;
  precompute?: { fabric?: { name?: string } };
  render?: { scene?: { render?: { method?: string; width?: number; height?: number } } };
}
export interface ServerInfo {
  version: string;
  health: string;
  queuedJobs: string;
  runningJobs: string;
  registeredWorkers: string;
  cachedFabrics: string;
  authRequired: boolean;
  tls: boolean;
  uptimeMs: string;
}
export interface WorkerInfo {
  workerId: string;
  capabilities?: { glVendor?: string; glRenderer?: string; softwareGl?: boolean; cores?: number; hostname?: string };
  state: string;
  currentJobId: string;
  registeredMs: string;
  lastSeenMs: string;
  jobsSucceeded: number;
  jobsFailed: number;
}
export interface ArtifactRef {
  sha256: string;
  size: string;
  name: string;
}
export interface CachedFabric {
  fabricKey: string;
  files: ArtifactRef[];
  totalBytes: string;
  pinned: boolean;
  createdMs: string;
  lastUsedMs: string;
}

export const ENDED_STATES = ["JOB_STATE_SUCCEEDED", "JOB_STATE_FAILED", "JOB_STATE_CANCELLED"];

export async function call<T>(method: string, body: object = {}): Promise<T> {
  const response = await fetch(`/api/v1/${method}`, {
    method: "POST",
    headers: { "Content-Type": "application/json" },
    body: JSON.stringify(body),
    credentials: "same-origin",
  });
  const text = await response.text();
  let json: { code?: string; message?: string } = {};
  try {
    json = text ? JSON.parse(text) : {};
  } catch {
    throw new ApiError(response.status, "INTERNAL", `${method}: the server answered ${response.status}, not JSON`);
  }
  if (!response.ok) throw new ApiError(response.status, json.code ?? "", json.message ?? response.statusText);
  return json as T;
}

export interface JobList {
  jobs: Job[];
  version: string;
  unchanged: boolean;
}

// Every job matching the filter, page by page (1000 a page), without their specs;
// none and `unchanged` when no job changed since `unlessVersion` (a previous list's).
export async function listJobs(states: string[], kinds: string[], unlessVersion = ""): Promise<JobList> {
  const list: JobList = { jobs: [], version: "", unchanged: false };
  let pageToken = "";
  do {
    const page = await call<{ jobs?: Job[]; nextPageToken?: string; version?: string; unchanged?: boolean }>(
      "ListJobs",
      { states, kinds, pageSize: 1000, pageToken, summary: true, unlessVersion: pageToken ? "" : unlessVersion },
    );
    if (!pageToken) {
      list.version = page.version ?? "";
      list.unchanged = page.unchanged ?? false;
    }
    list.jobs.push(...(page.jobs ?? []));
    pageToken = page.nextPageToken ?? "";
  } while (pageToken);
  return list;
}

export function artifactUrl(sha256: string): string {
  return `/api/v1/artifacts/${sha256}`;
}
