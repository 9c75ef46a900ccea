// Keeps the jetshell_tools library non-empty before any tools/<area>/ source exists.
