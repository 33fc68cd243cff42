// The configuration editor: the host's config as a tree of configurables. Every parameter shows
// its type, default, unit, range and doc from the registry's introspection (editor.schema);
// values are edited as YAML text; list slots take added, removed or swapped modules of any
// registered type of their kind; validation and saving go through the host (editor.validate,
// editor.save), which answers with `plugslam validate`'s own messages and writes only under its
// folder.

function el(tag, attrs = {}, ...children) {
  const e = document.createElement(tag);
  for (const [k, v] of Object.entries(attrs)) {
    if (k === "class") e.className = v;
    else if (k.startsWith("on")) e.addEventListener(k.slice(2), v);
    else if (v !== undefined && v !== null) e.setAttribute(k, v);
  }
  for (const c of children) if (c !== null && c !== undefined) e.append(c);
  return e;
}

/** The editor panel bound to a connection. */
export class ConfigEditor {
  constructor(container, connection) {
    this.container = container;
    this.connection = connection;
    this.schema = null;
    this.tree = null;
    this.types = new Map();
  }

  /** Loads the schema and the host's config; shows why when the host offers no editor. */
  async load() {
    this.container.replaceChildren(el("p", { class: "muted" }, "loading the configuration..."));
    try {
      this.schema = await this.connection.call("editor.schema");
      this.types = new Map(this.schema.types.map((t) => [t.name, t]));
      const cfg = await this.connection.call("editor.config");
      this.tree = cfg.tree;
      this.name = cfg.name;
      this.root = cfg.root;
      this.render();
    } catch (e) {
      this.container.replaceChildren(el("p", { class: "error" }, `no editor: ${e.message}`));
    }
  }

  schemaOf(module, isRoot) {
    if (isRoot) return this.schema.root;
    return this.types.get(module.type) || { params: [], slots: [], doc: "unknown type" };
  }

  render() {
    const toolbar = el(
      "div",
      { class: "editor-toolbar" },
      el("button", { id: "editor-validate", onclick: () => this.validate() }, "Validate"),
      el("input", {
        id: "editor-path",
        type: "text",
        value: this.savePath || "edited.yaml",
        title: `a .yaml path inside ${this.root}`,
        oninput: (e) => (this.savePath = e.target.value),
      }),
      el("button", { id: "editor-save", onclick: () => this.save() }, "Save"),
    );
    this.result = el("pre", { id: "editor-result", class: "editor-result" });
    const tree = el("div", { class: "editor-tree" }, this.moduleView(this.tree, "config", true));
    this.container.replaceChildren(
      el("div", { class: "muted" }, `${this.name} — saves go under ${this.root}`),
      toolbar,
      this.result,
      tree,
    );
  }

  moduleView(module, path, isRoot = false, slot = null, list = null, index = -1) {
    const schema = this.schemaOf(module, isRoot);
    const head = el("div", { class: "module-head" });
    if (isRoot) {
      head.append(el("b", {}, "config"));
    } else {
      head.append(el("span", { class: "path" }, path + " "));
      // Swap: any registered type of the slot's kind.
      const select = el("select", {
        class: "type-select",
        "data-path": path,
        onchange: (e) => {
          module.type = e.target.value;
          // Parameters of the old type mostly do not apply: keep those the new one has.
          const known = new Set((this.types.get(module.type)?.params || []).map((p) => p.name));
          module.params = module.params.filter((p) => known.has(p.key));
          module.slots = [];
          this.render();
        },
      });
      const kinds = this.schema.types.filter((t) => t.kind === slot.kind);
      if (!kinds.some((t) => t.name === module.type))
        select.append(el("option", { value: module.type }, module.type || "(default)"));
      for (const t of kinds) {
        const o = el("option", { value: t.name, title: t.doc }, t.name);
        if (t.name === module.type) o.selected = true;
        select.append(o);
      }
      head.append(select);
      if (list) {
        head.append(
          el("button", {
            class: "remove",
            title: "remove this module",
            "data-path": path,
            onclick: () => {
              list.splice(index, 1);
              this.render();
            },
          }, "remove"),
        );
      }
      if (schema.doc) head.append(el("div", { class: "doc" }, schema.doc));
    }
    const body = el("div", { class: "module-body" });
    body.append(this.paramsView(module, schema, path));
    for (const s of schema.slots || []) body.append(this.slotView(module, s, path));
    // Keys the schema does not know (typos, other types' keys): shown so they can be fixed.
    const known = new Set((schema.params || []).map((p) => p.name));
    for (const p of module.params)
      if (!known.has(p.key))
        body.append(el("div", { class: "param unknown" }, `${p.key}: ${p.value} (not a parameter of this type)`));
    return el("div", { class: "module", "data-path": path }, head, body);
  }

  paramsView(module, schema, path) {
    const table = el("table", { class: "params" });
    for (const p of schema.params || []) {
      const entry = module.params.find((x) => x.key === p.name);
      const range = p.min !== undefined ? `[${p.min}, ${p.max}]` : p.choices && p.choices.length ? p.choices.join(" | ") : "";
      const input = el("input", {
        type: "text",
        class: "param-input",
        "data-param": `${path}.${p.name}`,
        placeholder: p.default,
        value: entry ? entry.value : "",
        title: p.doc,
        onchange: (e) => {
          const v = e.target.value.trim();
          const at = module.params.findIndex((x) => x.key === p.name);
          if (v === "") {
            if (at >= 0) module.params.splice(at, 1); // back to the default
          } else if (at >= 0) {
            module.params[at].value = v;
          } else {
            module.params.push({ key: p.name, value: v });
          }
          e.target.classList.toggle("set", v !== "");
        },
      });
      if (entry) input.classList.add("set");
      table.append(
        el(
          "tr",
          {},
          el("td", { class: "pname" }, p.name),
          el("td", {}, input),
          el("td", { class: "ptype" }, p.type + (p.unit ? ` [${p.unit}]` : "")),
          el("td", { class: "prange" }, range),
          el("td", { class: "pdoc" }, `${p.doc} (default ${p.default})`),
        ),
      );
    }
    return table;
  }

  slotView(module, slotSchema, path) {
    let slot = module.slots.find((s) => s.key === slotSchema.name);
    const box = el("div", { class: "slot" });
    const title = el("div", { class: "slot-head" }, el("b", {}, slotSchema.name),
      ` ${slotSchema.list ? "list of " : ""}${slotSchema.kind}`, el("span", { class: "doc" }, ` — ${slotSchema.doc}`));
    box.append(title);
    const items = slot ? slot.items : [];
    items.forEach((item, i) => {
      const p = slotSchema.list ? `${path}.${slotSchema.name}[${i}]` : `${path}.${slotSchema.name}`;
      box.append(this.moduleView(item, p, false, slotSchema, slotSchema.list ? items : null, i));
    });
    if (slotSchema.list || items.length === 0) {
      const kinds = this.schema.types.filter((t) => t.kind === slotSchema.kind);
      if (kinds.length) {
        const select = el("select", { class: "add-select", "data-path": `${path}.${slotSchema.name}` });
        for (const t of kinds) select.append(el("option", { value: t.name, title: t.doc }, t.name));
        if (slotSchema.default) select.value = slotSchema.default;
        const add = el("button", {
          class: "add",
          "data-path": `${path}.${slotSchema.name}`,
          onclick: () => {
            if (!slot) {
              slot = { key: slotSchema.name, kind: slotSchema.kind, list: slotSchema.list, items: [] };
              module.slots.push(slot);
            }
            slot.items.push({ type: select.value, name: "", params: [], slots: [] });
            this.render();
          },
        }, "add");
        box.append(el("div", { class: "slot-add" }, select, add));
      }
    }
    return box;
  }

  show(kind, lines) {
    this.result.className = `editor-result ${kind}`;
    this.result.textContent = lines.join("\n");
  }

  async validate() {
    try {
      const r = await this.connection.call("editor.validate", { tree: this.tree });
      this.show(r.validation.ok ? "ok" : "error", r.validation.messages);
      return r;
    } catch (e) {
      this.show("error", [e.message]);
    }
  }

  async save() {
    const path = (this.savePath || "edited.yaml").trim();
    try {
      const r = await this.connection.call("editor.save", { path, tree: this.tree });
      this.show(r.validation.ok ? "ok" : "error", [`saved ${r.path}`, ...r.validation.messages]);
      return r;
    } catch (e) {
      this.show("error", [`not saved: ${e.message}`]);
    }
  }
}
