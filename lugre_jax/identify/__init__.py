"""Static friction identification (paper section 4.2): GA, PSO, GA-PSO, gradient refinement, baselines,
whole/piecewise schemes and uncertainty."""

# --- optimisers (owned by the optimiser module authors) ---
# --- end optimisers ---

# --- schemes, data, uncertainty ---
# --- end schemes ---
