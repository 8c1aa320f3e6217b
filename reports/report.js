// nightcap report: the large view of a diff's pictures. A click on a thumbnail opens it large,
// with zoom and the values of the texel under the pointer in both captures. The values are in
// data/<output>.js, loaded when the output is first opened: a script tag, because pages opened
// from file:// may not fetch files.
"use strict";

const nightcapReport = (() => {
  const values = new Map();   // output id -> Promise of {width, height, step, channels, a, b}
  const arrived = new Map();  // output id -> resolve function of that promise

  function halfToFloat(h) {
    const sign = h & 0x8000 ? -1 : 1, exponent = (h >> 10) & 31, mantissa = h & 1023;
    if (exponent === 0) return sign * mantissa * 2 ** -24;
    if (exponent === 31) return mantissa ? NaN : sign * Infinity;
    return sign * (1 + mantissa / 1024) * 2 ** (exponent - 15);
  }

  async function floats(packed, half) {
    const bytes = Uint8Array.from(atob(packed), (c) => c.charCodeAt(0));
    const stream = new Blob([bytes]).stream().pipeThrough(new DecompressionStream("deflate"));
    const buffer = await new Response(stream).arrayBuffer();
    return half ? Float32Array.from(new Uint16Array(buffer), halfToFloat) : new Float32Array(buffer);
  }

  // Called by data/<id>.js. Ids are kept as the strings of the thumbnails' data-output.
  function register(id, data) {
    const resolve = arrived.get(String(id));
    if (!resolve) return;
    arrived.delete(String(id));
    Promise.all([floats(data.a, data.half), floats(data.b, data.half)]).then(([a, b]) => resolve({ ...data, a, b }));
  }

  function load(id) {
    if (!values.has(id)) {
      values.set(id, new Promise((resolve) => arrived.set(id, resolve)));
      const script = document.createElement("script");
      script.src = `data/${id}.js`;
      document.head.appendChild(script);
    }
    return values.get(id);
  }

  const viewer = { id: null, view: null, zoom: 1, data: null, size: null };
  const names = { a: "reference (A)", b: "new (B)", difference: "|B − A|", flip: "FLIP" };

  function element(tag, attributes = {}, text = "") {
    const e = document.createElement(tag);
    for (const [k, v] of Object.entries(attributes)) e.setAttribute(k, v);
    if (text) e.textContent = text;
    return e;
  }

  function build() {
    const root = document.getElementById("viewer");
    if (root.firstChild) return root;
    const bar = element("div", { class: "toolbar" });
    bar.append(element("span", { class: "title" }));
    for (const view of Object.keys(names)) bar.append(element("button", { "data-switch": view }, names[view]));
    bar.append(
      element("button", { "data-zoom": "out", title: "zoom out (-)" }, "−"),
      element("button", { "data-zoom": "in", title: "zoom in (+)" }, "+"),
      element("button", { "data-zoom": "fit", title: "fit (0)" }, "fit"),
      element("button", { "data-close": "", title: "close (Esc)" }, "×"));
    const stage = element("div", { class: "stage" });
    stage.append(element("img", { alt: "" }));
    root.append(bar, stage, element("div", { class: "readout" }, "move the pointer over the picture"));
    root.addEventListener("click", (event) => {
      const t = event.target;
      if (t.dataset.switch) show(viewer.id, t.dataset.switch);
      if (t.dataset.zoom) zoom(t.dataset.zoom);
      if (t.hasAttribute("data-close")) close();
    });
    stage.addEventListener("wheel", (event) => {
      event.preventDefault();
      zoom(event.deltaY < 0 ? "in" : "out");
    }, { passive: false });
    stage.querySelector("img").addEventListener("mousemove", readout);
    return root;
  }

  function apply() {
    const img = document.querySelector("#viewer .stage img");
    if (!viewer.size) return;
    img.style.width = `${viewer.size.width * viewer.zoom}px`;
    img.style.height = `${viewer.size.height * viewer.zoom}px`;
  }

  function zoom(how) {
    const stage = document.querySelector("#viewer .stage");
    if (!viewer.size) return;
    if (how === "fit")
      viewer.zoom = Math.min(stage.clientWidth / viewer.size.width, stage.clientHeight / viewer.size.height);
    else viewer.zoom *= how === "in" ? 1.5 : 1 / 1.5;
    viewer.zoom = Math.min(Math.max(viewer.zoom, 0.25), 64);
    apply();
  }

  function show(id, view) {
    const thumbnail = document.querySelector(`img[data-output="${id}"][data-view="${view}"]`);
    if (!thumbnail) return;
    const root = build();
    root.hidden = false;
    const first = viewer.id !== id;
    viewer.id = id;
    viewer.view = view;
    const card = thumbnail.closest("section.output");
    root.querySelector(".title").textContent =
      `${card ? card.dataset.outputName : ""} — ${names[view]}`;
    for (const button of root.querySelectorAll("[data-switch]"))
      button.hidden = !document.querySelector(`img[data-output="${id}"][data-view="${button.dataset.switch}"]`);
    const img = root.querySelector(".stage img");
    img.onload = () => {
      const changed = !viewer.size || viewer.size.width !== img.naturalWidth;
      viewer.size = { width: img.naturalWidth, height: img.naturalHeight };
      if (first || changed) zoom("fit");
      else apply();
    };
    img.src = thumbnail.getAttribute("src").replace(/\.png$/, ".large.png");
    if (first) {
      viewer.data = null;
      root.querySelector(".readout").textContent = "loading the values…";
      load(id).then((data) => {
        if (viewer.id !== id) return;
        viewer.data = data;
        root.querySelector(".readout").textContent = "move the pointer over the picture";
      });
    }
  }

  function close() {
    document.getElementById("viewer").hidden = true;
  }

  function texel(data, values, index) {
    const out = [];
    for (let c = 0; c < data.channels; ++c) out.push(Number(values[index * data.channels + c]).toPrecision(5));
    return out.join(", ");
  }

  function readout(event) {
    const data = viewer.data;
    if (!data) return;
    const x = Math.min(data.width - 1, Math.floor(event.offsetX / viewer.zoom));
    const y = Math.min(data.height - 1, Math.floor(event.offsetY / viewer.zoom));
    if (x < 0 || y < 0) return;
    const i = y * data.width + x;
    document.querySelector("#viewer .readout").textContent =
      `texel (${x * data.step}, ${y * data.step})   A: ${texel(data, data.a, i)}   B: ${texel(data, data.b, i)}`;
  }

  document.addEventListener("click", (event) => {
    const img = event.target.closest("img[data-output]");
    if (img && !img.closest("#viewer")) show(img.dataset.output, img.dataset.view);
  });
  document.addEventListener("keydown", (event) => {
    const root = document.getElementById("viewer");
    if (!root || root.hidden) return;
    if (event.key === "Escape") close();
    if (event.key === "+" || event.key === "=") zoom("in");
    if (event.key === "-") zoom("out");
    if (event.key === "0") zoom("fit");
    const view = Object.keys(names)[Number(event.key) - 1];
    if (view) show(viewer.id, view);
  });

  return { values: register, show };
})();
