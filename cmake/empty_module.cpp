// Placeholder translation unit for a module whose sources are still being written.
