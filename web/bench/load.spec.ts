// How the dashboard holds up with many jobs (issue 27): BENCH_JOBS render jobs
// (default 1000) wait in a server without workers; BENCH_PAGES pages (default 5)
// show the jobs table, each polling once a second. Prints the time from navigation
// to the full table per page, the server's CPU over BENCH_SECONDS (default 30) with
// the pages open against as long with none, and the size and time of a ListJobs reply.
import { test, type Page } from "@playwright/test";
import { execFile } from "node:child_process";
import { readFileSync } from "node:fs";
import path from "node:path";
import { fileURLToPath } from "node:url";
import { promisify } from "node:util";

import { CLIENT_TOKEN, fixtures, LoomService } from "../tests/loom_service";

const here = path.dirname(fileURLToPath(import.meta.url));
const jobs = Number(process.env.BENCH_JOBS ?? 1000);
const pages = Number(process.env.BENCH_PAGES ?? 5);
const seconds = Number(process.env.BENCH_SECONDS ?? 30);

// The process's user + system CPU seconds (/proc/PID/stat fields 14 and 15).
function cpuSeconds(pid: number): number {
  const fields = readFileSync(`/proc/${pid}/stat`, "utf8").split(") ")[1].split(" ");
  return (Number(fields[11]) + Number(fields[12])) / 100;
}

async function serverCpu(service: LoomService, wallSeconds: number): Promise<number> {
  const before = cpuSeconds(service.serverPid);
  const start = Date.now();
  await new Promise((resolve) => setTimeout(resolve, wallSeconds * 1000));
  return (cpuSeconds(service.serverPid) - before) / ((Date.now() - start) / 1000);
}

test("dashboard load", async ({ browser }) => {
  const service = new LoomService();
  await service.start();
  try {
    const submitStart = Date.now();
    // Not execFileSync: the server's log must be read meanwhile (tests/loom_service.ts).
    await promisify(execFile)("/usr/bin/python3", [
      path.join(here, "submit_renders.py"),
      "--server",
      `127.0.0.1:${service.grpcPort}`,
      "--token-file",
      service.clientTokenFile,
      "--count",
      String(jobs),
      path.join(fixtures, "tiny_scene.json"),
    ]);
    console.log(`submitted ${jobs} render jobs in ${((Date.now() - submitStart) / 1000).toFixed(1)} s`);

    const idle = await serverCpu(service, seconds);
    const open: Page[] = [];
    for (let i = 0; i < pages; ++i) {
      const context = await browser.newContext();
      await context.request.post(`${service.url}/api/v1/login`, { data: { token: CLIENT_TOKEN } });
      const page = await context.newPage();
      const start = Date.now();
      await page.goto(`${service.url}/#/jobs`);
      await page.waitForFunction((n) => document.querySelectorAll("#jobs tbody tr").length === n, jobs + 1, {
        timeout: 120_000,
      });
      console.log(`page ${i + 1}: first full table (${jobs + 1} rows) ${Date.now() - start} ms after navigation`);
      open.push(page);
    }
    const busy = await serverCpu(service, seconds);
    console.log(
      `server CPU: ${(idle * 100).toFixed(1)}% of a core with no page, ` +
        `${(busy * 100).toFixed(1)}% with ${pages} pages open (${seconds} s each)`,
    );

    for (const summary of [true, false]) {
      const timing = await open[0].evaluate(async (summary) => {
        const times: number[] = [];
        let bytes = 0;
        for (let i = 0; i < 10; ++i) {
          const start = performance.now();
          const reply = await fetch("/api/v1/ListJobs", {
            method: "POST",
            headers: { "Content-Type": "application/json" },
            body: JSON.stringify({ pageSize: 1000, summary }),
          });
          bytes = (await reply.text()).length;
          times.push(performance.now() - start);
        }
        times.sort((a, b) => a - b);
        return { median: times[5], bytes };
      }, summary);
      console.log(
        `ListJobs of 1000 jobs${summary ? " (summary, as the page asks)" : " (whole)"}: ` +
          `${(timing.bytes / 1024).toFixed(0)} KiB, median ${timing.median.toFixed(1)} ms (5 pages polling meanwhile)`,
      );
    }
    const refresh = await open[0].evaluate(
      () =>
        new Promise<number>((resolve) => {
          // The page's own refresh: the time the main thread spends on one update.
          const observer = new PerformanceObserver((list) => {
            const longest = Math.max(0, ...list.getEntries().map((e) => e.duration));
            observer.disconnect();
            resolve(longest);
          });
          observer.observe({ type: "longtask", buffered: false });
          setTimeout(() => {
            observer.disconnect();
            resolve(0);
          }, 5000);
        }),
    );
    console.log(`longest main-thread task in 5 s of polling: ${refresh.toFixed(0)} ms (0: none over 50 ms)`);
  } finally {
    await service.stop();
  }
});
