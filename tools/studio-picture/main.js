// Foxglove Studio 1.48's App (the open-source @foxglove/studio-base bundle)
// with in-memory settings and layouts, opening the MCAP file named in the
// URL (?ds=remote-file&ds.url=...).
class Config {
  constructor(values) { this.values = new Map(Object.entries(values)); this.listeners = new Map(); }
  get(key) { return this.values.get(key); }
  async set(key, value) { this.values.set(key, value); for (const cb of this.listeners.get(key) ?? []) cb(value); }
  addChangeListener(key, cb) { if (!this.listeners.has(key)) this.listeners.set(key, new Set()); this.listeners.get(key).add(cb); }
  removeChangeListener(key, cb) { this.listeners.get(key)?.delete(cb); }
}
class Layouts {
  constructor(layouts) { this.items = new Map(layouts.map((l) => [l.id, l])); }
  async list() { return [...this.items.values()]; }
  async get(_ns, id) { return this.items.get(id); }
  async put(_ns, layout) { this.items.set(layout.id, layout); return layout; }
  async delete(_ns, id) { this.items.delete(id); }
  async importLayouts() {}
  async migrateUnnamespacedLayouts() {}
}
const layout = window.VREF_LAYOUT;
const { App, RemoteDataSourceFactory, McapLocalDataSourceFactory, initI18n } = window;
(async () => {
  if (initI18n) await initI18n();
  const now = new Date().toISOString();
  const stored = layout ? [{ id: "vref", name: "vref", permission: "CREATOR_WRITE", baseline: { data: layout, savedAt: now }, working: undefined, syncInfo: undefined }] : [];
  const config = new Config({ "ui.colorScheme": "dark", "telemetry.telemetryEnabled": false, "telemetry.crashReportingEnabled": false, "launchDefault": "web" });
  window.ReactDOM.render(
    window.React.createElement(App, {
      deepLinks: [window.location.href],
      appConfiguration: config,
      dataSources: [new RemoteDataSourceFactory(), new McapLocalDataSourceFactory()],
      layoutStorage: new Layouts(stored),
      extensionLoaders: [],
      enableGlobalCss: true,
    }),
    document.getElementById("root"),
  );
})();
