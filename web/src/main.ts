// The dashboard's router: #/jobs, #/jobs/<id>, #/fabrics, #/fabrics/<key>, #/workers,
// #/chart and #/login. A call refused for its token (401) shows the login page.
import { ApiError } from "./api.js";
import { chartPage } from "./chart.js";
import { h, replaceChildren } from "./dom.js";
import { fabricPage } from "./fabric_page.js";
import { fabricsPage } from "./fabrics.js";
import { jobPage } from "./job_page.js";
import { jobsPage } from "./jobs.js";
import { loginPage } from "./login.js";
import type { PageView } from "./page.js";
import type { Stop } from "./poll.js";
import { workersPage } from "./workers.js";

const routes: [RegExp, PageView][] = [
  [/^#\/jobs\/([\w-]+)$/, jobPage],
  [/^#\/jobs$/, jobsPage],
  [/^#\/fabrics\/([0-9a-f]+)$/, fabricPage],
  [/^#\/fabrics$/, fabricsPage],
  [/^#\/workers$/, workersPage],
  [/^#\/chart$/, chartPage],
  [/^#\/login$/, loginPage],
];

const main = document.getElementById("main") as HTMLElement;
const status = document.getElementById("status") as HTMLElement;
let stop: Stop = () => {};

function onError(error: unknown): void {
  if (error instanceof ApiError && error.status === 401) {
    if (location.hash !== "#/login") location.hash = "#/login";
    return;
  }
  status.textContent = error instanceof Error ? error.message : String(error);
  status.hidden = false;
}

function route(): void {
  stop();
  status.hidden = true;
  const hash = location.hash || "#/jobs";
  for (const [pattern, view] of routes) {
    const match = pattern.exec(hash);
    if (!match) continue;
    document.body.dataset.page = view === loginPage ? "login" : hash.split("/")[1];
    for (const link of document.querySelectorAll("nav a")) {
      link.classList.toggle("current", hash.startsWith(link.getAttribute("href") ?? "-"));
    }
    stop = view({ root: main, argument: match[1] ?? "", onError });
    return;
  }
  replaceChildren(main, h("p", {}, `No page ${hash}.`));
}

document.getElementById("sign-out")?.addEventListener("click", async () => {
  await fetch("/api/v1/logout", { method: "POST", headers: { "Content-Type": "application/json" } });
  location.hash = "#/login";
});
window.addEventListener("hashchange", route);
route();
