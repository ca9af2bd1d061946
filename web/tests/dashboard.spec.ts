// The dashboard against a real server, in Chromium (issue 27): nothing without the
// token; jobs submitted with the CLI appear, are reprioritised and cancelled from the
// page, progress and finish once a worker runs; the frame loads; the worker, the
// fabric and the chart show. LOOM_SCREENSHOTS=DIR saves each page there.
import { expect, test, type Page } from "@playwright/test";
import path from "node:path";

import { CLIENT_TOKEN, fixtures, LoomService } from "./loom_service";

const service = new LoomService();
const screenshots = process.env.LOOM_SCREENSHOTS;

async function screenshot(page: Page, name: string): Promise<void> {
  if (screenshots) await page.screenshot({ path: path.join(screenshots, `${name}.png`), fullPage: true });
}

function row(page: Page, jobId: string) {
  return page.locator(`#jobs tr[data-job="${jobId}"]`);
}

test.describe.configure({ mode: "serial" });

let precompute: any, render: any, other: any;

test.beforeAll(async () => {
  await service.start();
  // No worker yet: all three wait in the queue.
  precompute = service.submitPrecompute("tiny_settings.json");
  render = service.loom(
    "render",
    "--no-wait",
    "-o",
    path.join(service.dir, "frame.png"),
    path.join(fixtures, "tiny_scene.json"),
  ).job;
  other = service.submitPrecompute("wide_settings.json");
});

test.afterAll(async () => {
  await service.stop();
});

test("without the token nothing is shown", async ({ page, request }) => {
  await page.goto(service.url + "/#/jobs");
  await expect(page).toHaveURL(/#\/login$/);
  await expect(page.locator("#jobs")).toHaveCount(0);
  await expect(page.locator("body")).not.toContainText(precompute.id);

  await page.fill("#token", "not-the-token");
  await page.click("#sign-in");
  await expect(page.locator("#login-error")).toContainText("wrong bearer token");
  await expect(page).toHaveURL(/#\/login$/);

  for (const call of ["ListJobs", "ListFabrics", "ListWorkers", "GetServerInfo"]) {
    const reply = await request.post(`${service.url}/api/v1/${call}`, { data: {} });
    expect(reply.status(), call).toBe(401);
  }
  const wrong = await request.post(`${service.url}/api/v1/ListJobs`, {
    data: {},
    headers: { Authorization: "Bearer not-the-token" },
  });
  expect(wrong.status()).toBe(401);
  const frame = await request.get(`${service.url}/api/v1/artifacts/${"0".repeat(64)}`);
  expect(frame.status()).toBe(401);
  await screenshot(page, "login");
});

async function signIn(page: Page): Promise<void> {
  await page.goto(service.url + "/#/login");
  await page.fill("#token", CLIENT_TOKEN);
  await page.click("#sign-in");
  await expect(page).toHaveURL(/#\/jobs$/);
}

test("queued jobs appear; priority and cancel work from the page", async ({ page }) => {
  await signIn(page);
  for (const job of [precompute, render, other]) {
    await expect(row(page, job.id)).toContainText("queued");
  }
  await expect(row(page, render.id)).toContainText("render");

  const priority = row(page, other.id).locator("input.priority");
  await priority.fill("7");
  await priority.press("Enter");
  await expect.poll(() => service.loom("jobs", "show", other.id).priority ?? 0).toBe(7);
  await expect(row(page, other.id).locator("input.priority")).toHaveValue("7");

  await row(page, other.id).locator("button.cancel").click();
  await expect(row(page, other.id)).toContainText("cancelled");
  expect(service.loom("jobs", "show", other.id).state).toBe("JOB_STATE_CANCELLED");

  await page.selectOption("#state-filter", "CANCELLED");
  await expect(page.locator("#jobs tbody tr")).toHaveCount(1);
  await expect(row(page, other.id)).toBeVisible();
  await page.selectOption("#state-filter", "");
  await expect(page.locator("#jobs tbody tr")).toHaveCount(3);
});

test("jobs progress and finish once a worker runs; the frame loads", async ({ page }) => {
  await signIn(page);
  await service.startWorker();
  for (const job of [precompute, render]) {
    await expect(row(page, job.id)).toContainText("succeeded");
    await expect(row(page, job.id).locator(".stage")).toContainText("100%");
  }
  await screenshot(page, "jobs");

  await row(page, render.id).locator("a.job-link").click();
  await expect(page).toHaveURL(new RegExp(`#/jobs/${render.id}$`));
  const frame = page.locator("img.frame");
  await expect(frame).toHaveCount(1);
  await expect.poll(() => frame.evaluate((img: HTMLImageElement) => img.complete && img.naturalWidth)).toBe(96);
  expect(await frame.evaluate((img: HTMLImageElement) => img.naturalHeight)).toBe(64);
  await expect(page.locator("#log")).toContainText("leased by");
  await expect(page.locator("a.fabric-key")).toHaveText(precompute.fabric_key);
  await screenshot(page, "job");
});

test("the worker, the cache and the chart show", async ({ page }) => {
  await signIn(page);
  await page.click("nav >> text=Workers");
  const worker = page.locator("#workers tbody tr");
  await expect(worker).toHaveCount(1);
  await expect(worker).toContainText("llvmpipe");
  await expect(worker.locator("td").nth(6)).toHaveText("2");
  await expect(worker.locator("td").nth(7)).toHaveText("0");
  await expect(page.locator('#server [data-fact="queued"]')).toHaveText("0");
  await screenshot(page, "workers");

  await page.click("nav >> text=Fabrics");
  const fabric = page.locator(`#fabrics tr[data-fabric="${precompute.fabric_key}"]`);
  await expect(fabric).toContainText("dashboard knit");
  await expect(fabric).toContainText("svbrdf");
  await fabric.locator("button.pin").click();
  await expect(fabric).toContainText("Unpin");
  await expect.poll(() => service.loom("cache", "list").fabrics?.[0]?.pinned ?? false).toBe(true);
  await screenshot(page, "fabrics");

  await fabric.locator("a").first().click();
  await expect(page.locator("#settings")).toContainText("spatial_resolution");
  const preview = page.locator("img#preview");
  await expect.poll(() => preview.evaluate((img: HTMLImageElement) => img.complete && img.naturalWidth)).toBe(256);
  await expect(page.locator("#levels tbody tr").first()).toBeVisible();
  // Four levels (8², 4², 2², 1² texels), four maps each, one pixel per texel.
  const texels = page.locator("#texels img.texels");
  await expect(texels).toHaveCount(16);
  const albedo = page.locator('#texels img[alt="level 0 albedo"]');
  await expect.poll(() => albedo.evaluate((img: HTMLImageElement) => img.complete && img.naturalWidth)).toBe(8);
  await expect(page.locator("#texels dl")).toContainText("diffuse albedo");
  await screenshot(page, "fabric");

  await page.click("nav >> text=Chart");
  const points = page.locator("#chart circle.point");
  await expect.poll(() => points.count()).toBeGreaterThan(3);
  await points.first().hover();
  await expect(page.locator("#tooltip")).toContainText("PSNR");
  await screenshot(page, "chart");
});
