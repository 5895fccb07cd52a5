// PLACEHOLDER: being written (must be replaced before commit)
