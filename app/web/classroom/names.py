"""Display names that look like what they are: one name per look in the class.

A name is NFKC-normalised (full-width letters, ligatures and compatibility spaces become plain ones) and
refused when it holds a character that shows nothing or shows as something else: format characters (zero
width spaces and joiners, Unicode category Cf), spaces other than the plain one, line and paragraph
separators, private-use and unassigned code points, letters that show blank (Hangul fillers, the blank
braille pattern), and combining marks that do not follow a letter (or pile up on one).

Two names are one when their confusable skeletons are equal (Unicode TR39, section 4: "B\u043eb" with a
Cyrillic o is "Bob"). The standard library has no confusables table and the packages that carry one ship
megabytes of data for every script; a class types Latin, Cyrillic and Greek, so SKELETON maps the letters of
those scripts (and the digits) that look like a Latin letter, taken from TR39's confusables.txt. Case,
width and runs of spaces do not count either (app/store.py's name_key).
"""

from __future__ import annotations

import unicodedata

# TR39 confusables.txt for Latin, Cyrillic and Greek lookalikes, both cases, mapped to the Latin letter
_LOOKALIKES = {
    "a": "\u0430\u03b1", "A": "\u0410\u0391", "B": "\u0412\u0392\u03b2", "c": "\u0441\u03f2", "C": "\u0421\u03f9",
    "d": "\u0501", "e": "\u0435", "E": "\u0415\u0395", "g": "\u0261", "h": "\u04bb", "H": "\u041d\u0397",
    "i": "\u0456\u03b9\u0131", "I": "\u0406\u0399\u04c0", "j": "\u0458\u03f3", "J": "\u0408", "k": "\u03ba",
    "K": "\u041a\u039a", "l": "\u04cf\u01c0|1I", "M": "\u041c\u039c", "n": "\u0578", "N": "\u039d",
    "o": "\u043e\u03bf\u03c3", "O": "\u041e\u039f0", "p": "\u0440\u03c1", "P": "\u0420\u03a1", "q": "\u051b",
    "s": "\u0455", "S": "\u0405", "T": "\u0422\u03a4", "u": "\u03c5", "v": "\u03bd", "w": "\u051d",
    "x": "\u0445\u03c7", "X": "\u0425\u03a7", "y": "\u0443\u03b3", "Y": "\u04ae\u03a5", "Z": "\u0396",
}
SKELETON = str.maketrans({lookalike: latin for latin, lookalikes in _LOOKALIKES.items() for lookalike in lookalikes})
MULTI_CHARACTER = (("rn", "m"), ("vv", "w"), ("cl", "d"))  # TR39: pairs that read as one letter
REFUSED_CATEGORIES = {"Cc": "a control character", "Cf": "an invisible format character",
                      "Cs": "a surrogate", "Co": "a private-use character", "Cn": "an unassigned character",
                      "Zl": "a line separator", "Zp": "a paragraph separator"}
# letters and symbols that show as blank (TR39's default-ignorable and blank lookalikes outside Cf)
BLANK = frozenset("\u115f\u1160\u3164\uffa0\u2800")
MAX_MARKS = 2  # combining marks on one letter: more pile up over the next line (zalgo text)


class NameRefused(ValueError):
    """The one line saying what is wrong with a name."""


def display_name(name: str) -> str:
    """`name` NFKC-normalised and stripped, or NameRefused naming the first character that shows wrongly."""
    name = unicodedata.normalize("NFKC", name).strip()
    marks = 0
    for position, character in enumerate(name, 1):
        category = unicodedata.category(character)
        problem = REFUSED_CATEGORIES.get(category)
        if category == "Zs" and character != " ":
            problem = "a space other than the plain one"
        if character in BLANK:
            problem = "a character that shows as blank"
        if category in ("Mn", "Me"):
            marks += 1
            if position == 1 or not unicodedata.category(name[position - 2]).startswith(("L", "M")):
                problem = "a combining mark that is not on a letter"
            elif marks > MAX_MARKS:
                problem = f"more than {MAX_MARKS} combining marks on one letter"
        else:
            marks = 0
        if problem:
            raise NameRefused(f"a name cannot hold {problem} (U+{ord(character):04X} at character {position}): "
                              "type it with plain letters")
    return name


def skeleton(name: str) -> str:
    """What `name` looks like: equal skeletons are names a reader cannot tell apart."""
    text = unicodedata.normalize("NFD", unicodedata.normalize("NFKC", name)).translate(SKELETON).casefold()
    for pair, letter in MULTI_CHARACTER:
        text = text.replace(pair, letter)
    return " ".join(unicodedata.normalize("NFD", text).split())
