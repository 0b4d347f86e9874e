-- fmsvm's language server for Custom Macro B programs, Neovim 0.8 or later.
-- Put it in init.lua (or source it from there); `fmsvm` must be on PATH.
vim.filetype.add({ extension = { nc = "nc", tap = "nc", ngc = "nc", mpf = "nc", min = "nc" } })
vim.api.nvim_create_autocmd("FileType", {
  pattern = "nc",
  callback = function(args)
    local file = vim.api.nvim_buf_get_name(args.buf)
    local toml = vim.fs.find({ "fmsvm.toml" }, { upward = true, path = vim.fs.dirname(file) })[1]
    vim.lsp.start({
      name = "fmsvm",
      cmd = { "fmsvm", "lsp" },
      root_dir = toml and vim.fs.dirname(toml) or vim.fs.dirname(file),
    })
  end,
})
