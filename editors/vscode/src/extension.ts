// The fmsvm extension: starts `fmsvm lsp` for Custom Macro B files, shows a file's flat program,
// and debugs a macro with `fmsvm dap` (debug configuration type `fmsvm`).
import * as vscode from "vscode";
import {
  LanguageClient,
  LanguageClientOptions,
  ServerOptions,
} from "vscode-languageclient/node";

let client: LanguageClient | undefined;

export async function activate(context: vscode.ExtensionContext): Promise<void> {
  const command = vscode.workspace.getConfiguration("fmsvm").get<string>("path", "fmsvm");
  const server: ServerOptions = { command, args: ["lsp"] };
  const args = vscode.workspace.getConfiguration("fmsvm").get<string[]>("args", []);
  const options: LanguageClientOptions = {
    documentSelector: [{ scheme: "file", language: "fanuc-macro" }],
    // The workspace's `check` options: at start, and again whenever the setting changes.
    initializationOptions: args.length > 0 ? { args } : undefined,
    synchronize: { configurationSection: "fmsvm" },
  };
  client = new LanguageClient("fmsvm", "fmsvm", server, options);
  await client.start();
  // The macro debugger: `fmsvm dap` over standard input and output.
  context.subscriptions.push(
    vscode.debug.registerDebugAdapterDescriptorFactory("fmsvm", {
      createDebugAdapterDescriptor: () => new vscode.DebugAdapterExecutable(command, ["dap"]),
    }),
  );
  context.subscriptions.push(
    vscode.commands.registerCommand("fmsvm.expandFile", async () => {
      const editor = vscode.window.activeTextEditor;
      if (!editor || !client) {
        return;
      }
      try {
        const result = (await client.sendRequest("workspace/executeCommand", {
          command: "fmsvm.expand",
          arguments: [editor.document.uri.toString()],
        })) as { flat: string; blocks: number };
        const doc = await vscode.workspace.openTextDocument({
          content: result.flat,
          language: "fanuc-macro",
        });
        await vscode.window.showTextDocument(doc, vscode.ViewColumn.Beside);
      } catch (e) {
        vscode.window.showErrorMessage(`fmsvm: ${e instanceof Error ? e.message : String(e)}`);
      }
    }),
  );
}

export async function deactivate(): Promise<void> {
  await client?.stop();
}
