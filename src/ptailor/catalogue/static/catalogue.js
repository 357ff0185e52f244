// ptailor catalogue: sort the garments' table by a column, filter it by status, gate, name.
// The project's own script, no library; the page works without it (input order, all rows).
"use strict";
(function () {
  var table = document.getElementById("catalogue");
  if (!table) { return; }
  var tbody = table.tBodies[0];
  var heads = Array.prototype.slice.call(table.tHead.rows[0].cells);
  var status = document.getElementById("filter-status");
  var gate = document.getElementById("filter-gate");
  var name = document.getElementById("filter-name");
  var count = document.getElementById("shown-count");

  function position(row) { return Number(row.cells[0].getAttribute("data-sort")); }

  function value(row, col, type) {
    var cell = row.cells[col];
    var text = cell.hasAttribute("data-sort") ? cell.getAttribute("data-sort") : cell.textContent;
    if (type === "number") { return text === "" ? null : Number(text); }
    return text.trim().toLowerCase();
  }

  function sortBy(th, col) {
    var dir = th.getAttribute("aria-sort") === "ascending" ? -1 : 1;
    var type = th.getAttribute("data-type");
    heads.forEach(function (h) { h.removeAttribute("aria-sort"); });
    th.setAttribute("aria-sort", dir === 1 ? "ascending" : "descending");
    var rows = Array.prototype.slice.call(tbody.rows);
    rows.sort(function (a, b) {
      var x = value(a, col, type), y = value(b, col, type);
      if (x === null || y === null) {  // no value: last, whichever the direction
        if (x === null && y === null) { return position(a) - position(b); }
        return x === null ? 1 : -1;
      }
      if (x < y) { return -dir; }
      if (x > y) { return dir; }
      return position(a) - position(b);  // ties keep the input order
    });
    rows.forEach(function (r) { tbody.appendChild(r); });
  }

  function filter() {
    var s = status.value, g = gate.value, n = name.value.trim().toLowerCase(), shown = 0;
    Array.prototype.forEach.call(tbody.rows, function (row) {
      var gates = (row.getAttribute("data-gates") || "").split(" ");
      var text = row.cells[1].textContent.toLowerCase();  // the name, path and note
      var keep = (!s || row.getAttribute("data-status") === s) &&
        (!g || gates.indexOf(g) >= 0) && (!n || text.indexOf(n) >= 0);
      row.hidden = !keep;
      if (keep) { shown += 1; }
    });
    count.textContent = shown + " of " + tbody.rows.length + " garments shown";
  }

  heads.forEach(function (th, col) {
    var button = th.querySelector("button");
    if (button) { button.addEventListener("click", function () { sortBy(th, col); }); }
  });
  status.addEventListener("change", filter);
  gate.addEventListener("change", filter);
  name.addEventListener("input", filter);
  document.getElementById("controls").hidden = false;
  filter();
})();
