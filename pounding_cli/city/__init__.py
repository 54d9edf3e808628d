"""City scale: blocks of buildings (block.py), contact candidates within reach (reach.py)."""
