// The login page: the client token (the server's --client-token-file) is checked by
// the server and kept in an HttpOnly cookie.
import { ApiError } from "./api.js";
import { h, replaceChildren } from "./dom.js";
import type { PageView } from "./page.js";

export const loginPage: PageView = ({ root }) => {
  const input = h("input", { id: "token", type: "password", autocomplete: "current-password", required: true });
  const message = h("p", { class: "error", id: "login-error" });
  const form = h(
    "form",
    { class: "login" },
    h("h1", {}, "Loom"),
    h("label", { for: "token" }, "Client token"),
    input,
    h("button", { type: "submit", id: "sign-in" }, "Sign in"),
    message,
  );
  form.addEventListener("submit", async (event) => {
    event.preventDefault();
    const response = await fetch("/api/v1/login", {
      method: "POST",
      headers: { "Content-Type": "application/json" },
      body: JSON.stringify({ token: input.value }),
    });
    if (response.ok) {
      location.hash = "#/jobs";
      return;
    }
    const body = await response.json().catch(() => ({}));
    message.textContent = new ApiError(response.status, body.code ?? "", body.message ?? "refused").message;
  });
  replaceChildren(root, form);
  input.focus();
  return () => {};
};
