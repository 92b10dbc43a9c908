// Filled by the baker work (issue 3).
