"""Paper reproductions (``passive-assoc reproduce NAME``): each runs a paper's experiment with
fixed seeds and reports the project's figures beside the paper's (EXPERIMENTS.md)."""
