"""Shared labelling of the plotting scripts' grids of maps (scripts/plot_*.py): one panel per (row, column),
each a term over Visibility (x) and N.L (y)."""


def label_panel(ax, i, j, n_rows, title, ylabel, fontsize=8, title_size=None, every_title=False):
    """Labels panel (i, j) of an n_rows-row grid: `title` on the top row (on every row with every_title),
    `ylabel` in the left column, "Visibility" under the bottom row, small tick labels everywhere."""
    if i == 0 or every_title:
        ax.set_title(title, fontsize=title_size or fontsize)
    if j == 0:
        ax.set_ylabel(ylabel, fontsize=fontsize)
    if i == n_rows - 1:
        ax.set_xlabel("Visibility", fontsize=fontsize)
    ax.tick_params(labelsize=6)
