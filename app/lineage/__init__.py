"""Lineage for people: a run's family trees read and described (family_tree), drawn (drawing), and one
breeding shown step by step (breeding)."""
