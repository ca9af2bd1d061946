// What every page gets: its root element, the route's argument, and the router's
// error handler (a 401 sends the user to the login page).
import type { Stop } from "./poll.js";

export interface Page {
  root: HTMLElement;
  argument: string;
  onError: (error: unknown) => void;
}

export type PageView = (page: Page) => Stop;

// The poll interval of live pages.
export const REFRESH_MS = 1000;
