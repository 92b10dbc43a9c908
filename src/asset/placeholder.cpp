// Filled by the asset work (issue 3).
