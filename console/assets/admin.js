/* trustcbr console: the researcher's page script (served as /assets/admin.js).
 * Sends the admin token as a Bearer token to GET /api/admin/participants and shows the rows
 * in a table. The token stays in the input only (nothing is stored). */
"use strict";

(function () {
  const $ = (id) => document.getElementById(id);
  const COLUMNS = ["participant", "condition", "phase", "commands", "behaviors", "ratings", "events"];
  const NUMERIC = new Set(["commands", "behaviors", "ratings", "events"]);

  $("admin-form").addEventListener("submit", async (e) => {
    e.preventDefault();
    const alertBox = $("admin-alert");
    alertBox.textContent = "";
    $("admin-status").textContent = "Loading…";
    let rows;
    try {
      const res = await fetch("/api/admin/participants", {
        headers: { Authorization: "Bearer " + $("admin-token").value.trim() },
        cache: "no-store",
      });
      const data = await res.json().catch(() => null);
      if (!res.ok) throw new Error((data && data.error) || "HTTP " + res.status);
      rows = Array.isArray(data) ? data : [];
    } catch (err) {
      $("admin-status").textContent = "";
      alertBox.textContent = "Could not list the participants: " + err.message;
      return;
    }
    const body = $("participants").tBodies[0];
    body.textContent = "";
    for (const row of rows) {
      const tr = document.createElement("tr");
      for (const c of COLUMNS) {
        const td = document.createElement(c === "participant" ? "th" : "td");
        if (c === "participant") td.setAttribute("scope", "row");
        if (NUMERIC.has(c)) td.className = "num";
        td.textContent = row[c] == null ? "" : String(row[c]);
        tr.appendChild(td);
      }
      body.appendChild(tr);
    }
    $("participants").hidden = false;
    $("admin-status").textContent = rows.length + (rows.length === 1 ? " participant." : " participants.");
  });
})();
