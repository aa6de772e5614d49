// help.js -- the help of `cosim app` (bundled by cosim/app/export.py after app.js): the "help"
// button opens the dialog #help of index.html (how to read each plot, weave and capsize, the
// rides), and a one-line explanation of weave and capsize is put beside their speeds.
(function () {
  "use strict";
  const $ = (id) => document.getElementById(id);

  function build() {
    const dialog = $("help"), open = $("help-open");
    if (dialog && open) {
      open.addEventListener("click", () => {
        if (typeof dialog.showModal === "function") dialog.showModal(); else dialog.setAttribute("open", "");
      });
    }
    const speeds = $("speeds");
    if (speeds && !$("speeds-about")) {
      const about = document.createElement("p");
      about.id = "speeds-about";
      about.className = "note";
      about.textContent = "Weave: below this speed the bicycle sways from side to side, more and more. Capsize: " +
        "above this speed it slowly leans over and falls. Between the two it rights itself (self-stable). " +
        "More under \u201chelp\u201d.";
      const stable = $("self-stable");  // app.js's line under the speeds, if it made one
      (stable && stable.previousElementSibling === speeds ? stable : speeds).after(about);
    }
  }

  if (document.readyState === "loading") document.addEventListener("DOMContentLoaded", build);
  else build();
})();
