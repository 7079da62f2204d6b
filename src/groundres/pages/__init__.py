"""Self-contained HTML pages: the report of one case and the gallery of the seed paper's figures.

A page is one file: its pictures are embedded as ``data:`` URIs and its style
sheet is inline, so it opens offline, can be mailed, and prints (a print
style sheet keeps each figure and table on one sheet). Text comes from
Jinja2 templates shipped in the package (``groundres/templates``) with
autoescaping on, so a case's title or text can never become markup.

Every number a page shows that summary.json also holds carries its full
value and its place in summary.json: ``<span class="num" data-key="..."
data-value="...">``. A reader sees the rounded text; a test or a script can
check the page against the data.
"""
