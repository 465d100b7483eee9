// MathJax 3 typesets only what pymdownx.arithmatex (generic mode) marked: the equations of the
// docstrings (converted from reStructuredText by scripts/griffe_rst.py) and of the pages.
window.MathJax = {
  tex: {
    inlineMath: [["\\(", "\\)"]],
    displayMath: [["\\[", "\\]"]],
  },
  options: {
    ignoreHtmlClass: ".*",
    processHtmlClass: "arithmatex",
  },
};
