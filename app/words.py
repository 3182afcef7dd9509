"""How the app words a count for people, everywhere it shows one (the CLI, the UI, recordings, the class's
tables): one place, so "1 rules" cannot come back in one corner."""


def plural(count: int, word: str, many: str | None = None) -> str:
    """'1 rule', '2 rules'; `many` for a word that is not made plural with an s ('entry', 'entries')."""
    return f"{count} {word if count == 1 else many or word + 's'}"
