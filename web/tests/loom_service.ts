// A real Loom service for the browser tests: loom-server with tokens and the
// dashboard on free loopback ports, remote workers started on demand, and the
// `loom` CLI. Binaries come from LOOM_BUILD_DIR (default ../build).
import { execFileSync, spawn, type ChildProcess } from "node:child_process";
import { mkdtempSync, rmSync, writeFileSync } from "node:fs";
import { tmpdir } from "node:os";
import path from "node:path";
import { fileURLToPath } from "node:url";

const here = path.dirname(fileURLToPath(import.meta.url));

const buildDir = process.env.LOOM_BUILD_DIR ?? path.resolve(here, "../../build");
export const fixtures = path.resolve(here, "fixtures");
export const CLIENT_TOKEN = "dashboard-client-token";

// Resolves with the first match of `pattern` in the process's output.
function waitForLine(child: ChildProcess, pattern: RegExp, what: string): Promise<RegExpMatchArray> {
  return new Promise((resolve, reject) => {
    let seen = "";
    const onData = (data: Buffer) => {
      seen += data.toString();
      const match = seen.match(pattern);
      if (match) {
        child.stdout?.off("data", onData);
        child.stderr?.off("data", onData);
        resolve(match);
      }
    };
    child.stdout?.on("data", onData);
    child.stderr?.on("data", onData);
    child.once("exit", (code) => reject(new Error(`${what} exited (${code}) before saying ${pattern}:\n${seen}`)));
  });
}

// Keeps reading a child's output (the service logs a line per job): a pipe nobody
// reads fills, and the child blocks writing to it.
function drained(child: ChildProcess): ChildProcess {
  child.stdout?.resume();
  child.stderr?.resume();
  return child;
}

function stopped(child: ChildProcess): Promise<void> {
  if (child.exitCode !== null || child.signalCode !== null) return Promise.resolve();
  return new Promise((resolve) => {
    child.once("exit", () => resolve());
    child.kill("SIGTERM");
  });
}

export class LoomService {
  readonly dir = mkdtempSync(path.join(tmpdir(), "loom-dashboard-"));
  readonly clientTokenFile = path.join(this.dir, "client.token");
  readonly workerTokenFile = path.join(this.dir, "worker.token");
  grpcPort = 0;
  httpPort = 0;
  private server?: ChildProcess;
  private workers: ChildProcess[] = [];

  // Without local workers: jobs wait in the queue until startWorker().
  async start(): Promise<void> {
    writeFileSync(this.clientTokenFile, CLIENT_TOKEN + "\n");
    writeFileSync(this.workerTokenFile, "dashboard-worker-token\n");
    this.server = drained(
      spawn(path.join(buildDir, "server/loom-server"), [
        "--data",
        path.join(this.dir, "data"),
        "--listen",
        "127.0.0.1:0",
        "--http",
        "127.0.0.1:0",
        "--local-workers",
        "0",
        "--client-token-file",
        this.clientTokenFile,
        "--worker-token-file",
        this.workerTokenFile,
      ]),
    );
    const [grpc, http] = await Promise.all([
      waitForLine(this.server, /listening on \S+ \(port (\d+)\)/, "loom-server"),
      waitForLine(this.server, /dashboard on http:\/\/127\.0\.0\.1:(\d+)\//, "loom-server"),
    ]);
    this.grpcPort = Number(grpc[1]);
    this.httpPort = Number(http[1]);
  }

  get serverPid(): number {
    return this.server?.pid ?? 0;
  }

  get url(): string {
    return `http://127.0.0.1:${this.httpPort}`;
  }

  async startWorker(): Promise<void> {
    const worker = drained(
      spawn(path.join(buildDir, "worker/loom-worker"), [
        "--server",
        `127.0.0.1:${this.grpcPort}`,
        "--token-file",
        this.workerTokenFile,
        "--software",
        "--lease-wait",
        "1",
      ]),
    );
    this.workers.push(worker);
    await waitForLine(worker, /registered as/, "loom-worker");
  }

  // Submits a precompute of the fixtures' knit with the settings in fixtures/`settings`,
  // not waiting for it: its job.
  submitPrecompute(settings: string): any {
    const args = ["--no-wait", "--settings", path.join(fixtures, settings), path.join(fixtures, "knit.json")];
    return this.loom("fabric", "precompute", ...args).job;
  }

  // `loom --json ARGS…`: its JSON reply.
  loom(...args: string[]): any {
    const out = execFileSync(
      path.join(buildDir, "client/loom"),
      ["--server", `127.0.0.1:${this.grpcPort}`, "--token-file", this.clientTokenFile, "--json", ...args],
      { encoding: "utf8" },
    );
    return JSON.parse(out);
  }

  async stop(): Promise<void> {
    await Promise.all(this.workers.map(stopped));
    if (this.server) await stopped(this.server);
    rmSync(this.dir, { recursive: true, force: true });
  }
}
