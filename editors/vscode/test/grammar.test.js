// The TextMate grammar (syntaxes/fanuc-macro.tmLanguage.json) under VS Code's own engine
// (vscode-textmate with Oniguruma): chosen tokens of real programs get the scopes a theme colours,
// and every character of the shipped programs but spaces is in some scope of the grammar's own.
// `npm test` runs it.
"use strict";
const fs = require("fs");
const path = require("path");
const assert = require("assert");
const vsctm = require("vscode-textmate");
const oniguruma = require("vscode-oniguruma");

const root = path.join(__dirname, "..", "..", "..");
const grammarPath = path.join(__dirname, "..", "syntaxes", "fanuc-macro.tmLanguage.json");

async function loadGrammar() {
  const wasm = fs.readFileSync(require.resolve("vscode-oniguruma/release/onig.wasm"));
  await oniguruma.loadWASM(wasm.buffer.slice(wasm.byteOffset, wasm.byteOffset + wasm.byteLength));
  const registry = new vsctm.Registry({
    onigLib: Promise.resolve({
      createOnigScanner: (patterns) => new oniguruma.OnigScanner(patterns),
      createOnigString: (s) => new oniguruma.OnigString(s),
    }),
    loadGrammar: async () =>
      vsctm.parseRawGrammar(fs.readFileSync(grammarPath, "utf8"), grammarPath),
  });
  return registry.loadGrammar("source.fanuc-macro");
}

// Each line's tokens: [text, scopes] with the root scope left out.
function tokenize(grammar, text) {
  let stack = vsctm.INITIAL;
  return text.split(/\r?\n/).map((line) => {
    const r = grammar.tokenizeLine(line, stack);
    stack = r.ruleStack;
    return r.tokens.map((t) => [line.slice(t.startIndex, t.endIndex), t.scopes.slice(1)]);
  });
}

// The scopes of the token that is exactly `text` on a line of `source`.
function scopesOf(grammar, source, text) {
  for (const line of tokenize(grammar, source)) {
    for (const [t, scopes] of line) {
      if (t === text) return scopes;
    }
  }
  throw new Error(`no token \`${text}\` in ${source}`);
}

function expect(grammar, source, text, scope) {
  const scopes = scopesOf(grammar, source, text);
  assert.ok(
    scopes.some((s) => s.startsWith(scope)),
    `\`${text}\` in \`${source}\`: ${JSON.stringify(scopes)} has no ${scope}`,
  );
}

async function main() {
  const g = await loadGrammar();
  // Loops and branches, written without spaces as controls take them.
  const loop = "N10WHILE[#1LE50]DO1\nIF[#2GT#1]GOTO20\nIF[#3EQ0]THEN#4=1\nEND1";
  expect(g, loop, "WHILE", "keyword.control.loop");
  expect(g, loop, "DO", "keyword.control.loop");
  expect(g, loop, "END", "keyword.control.loop");
  expect(g, loop, "IF", "keyword.control.conditional");
  expect(g, loop, "THEN", "keyword.control.conditional");
  expect(g, loop, "GOTO", "keyword.control.goto");
  expect(g, loop, "LE", "keyword.operator.comparison");
  expect(g, loop, "GT", "keyword.operator.comparison");
  expect(g, loop, "EQ", "keyword.operator.comparison");
  expect(g, loop, "N", "keyword.other.sequence-number");
  expect(g, loop, "10", "entity.name.label.sequence-number");
  expect(g, loop, "1", "variable.other");
  expect(g, loop, "50", "constant.numeric");
  // The two-letter abbreviations fmsvm's lexer reads (upper case only).
  const short = "WH[#1LT3]DO2\nEN2\n#5=SI[30]+AT[1]/[2]";
  expect(g, short, "WH", "keyword.control.loop");
  expect(g, short, "EN", "keyword.control.loop");
  expect(g, short, "SI", "support.function");
  expect(g, short, "AT", "support.function");
  expect(g, "#2=SIN#1", "SIN", "support.function");
  // Functions, operators and nested brackets in an assignment.
  const expr = "#24=ROUND[SQRT[#1*#1+#2*#2]]\n#3=#1 MOD 2\n#4=[#1 AND 3] OR [#2 XOR 1]";
  expect(g, expr, "ROUND", "support.function");
  expect(g, expr, "SQRT", "support.function");
  expect(g, expr, "=", "keyword.operator.assignment");
  expect(g, expr, "*", "keyword.operator.arithmetic");
  expect(g, expr, "MOD", "keyword.operator.word");
  expect(g, expr, "XOR", "keyword.operator.logical");
  // Motion: codes, addresses, the program number, comments, block delete, the tape marker.
  const motion = "%\nO7118 (HEMISPHERE R40)\n/N20 G01 X#24 Y-50. Z[#26-1] F1000\nG65 P9010 A1.5\nM30\n%";
  expect(g, motion, "%", "keyword.other.tape-marker");
  expect(g, motion, "7118", "entity.name.function.program");
  expect(g, motion, "HEMISPHERE R40", "comment.block");
  expect(g, motion, "/", "keyword.other.block-delete");
  expect(g, motion, "01", "keyword.other.g-code");
  expect(g, motion, "65", "keyword.other.g-code");
  expect(g, motion, "30", "keyword.other.m-code");
  expect(g, motion, "X", "variable.parameter.address");
  expect(g, "G81 XI10 Y50", "XI", "variable.parameter.address");
  expect(g, motion, "Y", "variable.parameter.address");
  expect(g, motion, "50.", "constant.numeric");
  // DPRNT: its body is text, with #n[format] variables.
  const print = "POPEN\nDPRNT[X#5021[44]**Y#5022[53]]\nPCLOS";
  expect(g, print, "DPRNT", "support.function.print");
  expect(g, print, "X", "string.unquoted.print");
  expect(g, print, "5021", "variable.other");
  expect(g, print, "44", "constant.numeric.format");
  expect(g, print, "POPEN", "keyword.other.channel");
  // A comment with brackets and keywords inside is only a comment.
  expect(g, "G0 X1 (IF[#1] GOTO 5)", "IF[#1] GOTO 5", "comment.block");

  // Every character of the shipped programs but spaces is in one of the grammar's scopes.
  const programs = [];
  const walk = (dir) => {
    for (const e of fs.readdirSync(dir, { withFileTypes: true })) {
      const p = path.join(dir, e.name);
      if (e.isDirectory()) walk(p);
      else if (e.name.endsWith(".nc")) programs.push(p);
    }
  };
  walk(path.join(root, "samples"));
  walk(path.join(root, "tests"));
  // tests/m98m99 holds LinuxCNC's own O-word programs (o100 sub, O<name>), which fmsvm refuses.
  const macroB = programs.filter((p) => !p.includes(`${path.sep}m98m99${path.sep}`));
  const unscoped = [];
  for (const file of macroB) {
    const lines = tokenize(g, fs.readFileSync(file, "utf8"));
    lines.forEach((tokens, i) => {
      for (const [text, scopes] of tokens) {
        if (scopes.length === 0 && text.trim() !== "") {
          unscoped.push(`${path.relative(root, file)}:${i + 1}: \`${text}\``);
        }
      }
    });
  }
  assert.deepStrictEqual(unscoped, [], "characters in no scope");
  console.log(`grammar: ${macroB.length} programs and every chosen token scoped`);
}

main().catch((e) => {
  console.error(e.message || e);
  process.exit(1);
});
