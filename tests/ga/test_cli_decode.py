"""`soccer-lab rules decode NOTATION` through typer's CliRunner."""

from typer.testing import CliRunner

from soccer_lab.app.cli import rules

RUNNER = CliRunner()


def decode(notation):
    return RUNNER.invoke(rules.app, ["decode", notation])


def test_decode_prints_the_chapters_fig_6_rule():
    result = decode("(B,L,A) (B,A,O) (G,nF,O) (Dr,n,L)")
    assert result.exit_code == 0
    assert result.stdout == "if (Ball is Left and Ball is At) or Goal is not Far then Dribble Low\n"


def test_decode_prints_the_three_rules_of_fig_7():
    result = decode("(B,N,O) (B,nF,A) (G,N,A) (RB,n,L) (B,A,A) (G,vN,O) (KG,n,M) (B,L,A) (T,L,n)")
    assert result.exit_code == 0
    assert result.stdout.splitlines() == [
        "if (Ball is Near or Ball is not Far) and Goal is Near then RunTowardBall Low",
        "if Ball is At and Goal is VeryNear then KickTowardGoal MediumPower",
        "if Ball is Left then Turn Left",
    ]


def test_decode_says_when_no_rule_is_valid():
    result = decode("(T,L,n) (B,N,O)")
    assert result.exit_code == 0 and result.stdout.startswith("# no valid rule")


def test_malformed_notation_is_one_line_and_exit_status_2():
    result = decode("(B,N,O) (RB,n,Loud)")
    assert result.exit_code == 2
    assert result.stderr == ("error: malformed chromosome notation: gene 2 (RB,n,Loud) at column 9: "
                             "unknown power 'Loud' (expected one of vL, L, sL, M, sH, H, vH, or n for Null)\n")
