// The bundled extension (out/extension.js, made by `npm run compile`) loads with nothing but VS
// Code's own `vscode` module beside it (a stand-in here): every other module it needs, the language
// client among them, is inside the bundle, so the package needs no node_modules. `npm test` runs it.
"use strict";
const assert = require("assert");
const Module = require("module");
const path = require("path");

// `vscode` as a stand-in whose every member is a harmless function or value.
const stub = new Proxy(function () {}, {
  get: (_, key) => (key === "__esModule" ? false : stub),
  apply: () => stub,
  construct: () => stub,
});
const resolve = Module._resolveFilename;
const required = [];
const bundle = path.join(__dirname, "..", "out", "extension.js");
Module._resolveFilename = function (request, parent, ...rest) {
  if (request === "vscode") return "vscode";
  if (parent && parent.filename === bundle) required.push(request);
  return resolve.call(this, request, parent, ...rest);
};
require.cache.vscode = { id: "vscode", filename: "vscode", loaded: true, exports: stub };

const extension = require(bundle);
assert.strictEqual(typeof extension.activate, "function", "activate");
assert.strictEqual(typeof extension.deactivate, "function", "deactivate");
// Only Node's own modules are looked up outside the bundle.
const outside = required.filter((r) => !Module.builtinModules.includes(r.replace(/^node:/, "")));
assert.deepStrictEqual(outside, [], "modules outside the bundle");
console.log("bundle: loads with only vscode and Node's modules outside it");
