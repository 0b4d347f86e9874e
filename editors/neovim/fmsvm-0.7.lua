-- fmsvm's language server for Custom Macro B programs, Neovim 0.7 or later.
-- Put it in init.lua (or source it from there); `fmsvm` must be on PATH.
vim.cmd([[autocmd BufRead,BufNewFile *.nc,*.tap,*.ngc,*.mpf,*.min set filetype=nc]])
local fmsvm_clients = {}
vim.api.nvim_create_autocmd("FileType", {
  pattern = "nc",
  callback = function(args)
    -- The workspace is the folder of the nearest fmsvm.toml above the file, else the file's folder.
    local dir = vim.fn.fnamemodify(vim.api.nvim_buf_get_name(args.buf), ":p:h")
    local toml = vim.fn.findfile("fmsvm.toml", dir .. ";")
    local root = toml ~= "" and vim.fn.fnamemodify(toml, ":p:h") or dir
    if not fmsvm_clients[root] then
      fmsvm_clients[root] = vim.lsp.start_client({ name = "fmsvm", cmd = { "fmsvm", "lsp" }, root_dir = root })
    end
    vim.lsp.buf_attach_client(args.buf, fmsvm_clients[root])
  end,
})
