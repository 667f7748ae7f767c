#!/usr/bin/env python3
"""Write psim's man page and bash completion from the built program's help.

usage: psim_docs.py --psim BIN --version V --description TEXT --man OUT.1
                    --man-template TEMPLATE --docdir DIR
                    --completion-template TEMPLATE --completion OUT

The page's synopsis, description, options, commands and models come from
the program: `psim --help`, `psim CMD --help` for each subcommand the main
help's usage lines name, and `psim models`; only the layout (and the NAME
line, the project's description) is this script's.  The sections no help
text holds (exit status, environment, examples, see also) come from the
man template (cmake/psim-man.in), whose example commands and options are
checked against the help texts: an option the program does not list stops
the build.  The completion's lists (subcommands, each command's
options, which of them take a value or a file, the models and their
options) come from the same texts, so neither can drift from the program.
The output is deterministic: no date, no path.  Python 3 standard library
only (cmake/install.cmake runs it at build time).
"""
import argparse
import os
import re
import subprocess
import sys

# An option line: at most 7 spaces, then a dash ("  -m, --model NAME  text",
# "      --steps S     text"); a deeper line continues the text above.
OPTION_LINE = re.compile(r"^ {1,7}-")
# Its head: "-m, --model NAME", "-s S", "--naive"; a value's name starts
# with a capital ("N", "K=V", "FILE.xml").  The text follows after spaces
# (one only where the head is long: "--force-stats --option stats=1: ...").
META = r"[A-Z][A-Za-z0-9_.=]*"
OPTION_HEAD = re.compile(
    r"^\s+(?:(?P<short>-[A-Za-z0-9])(?: (?P<meta1>%s))?(?:, |(?=\s|$)))?"
    r"(?:(?P<long>--[A-Za-z0-9][A-Za-z0-9-]*)(?: (?P<meta2>%s))?)?"
    r"(?:\s+(?P<text>\S.*))?$" % (META, META))
# Options in a usage line: "[--pin POLICY]", "[--topology FILE.xml]".
USAGE_OPTION = re.compile(r"\[(--[a-z][a-z0-9-]*)(?: ([^\]\s]+))?\]")
NAME = re.compile(r"^-{1,2}[A-Za-z0-9][A-Za-z0-9-]*$")
WORD = re.compile(r"^[a-z0-9][a-z0-9_-]*$")


def die(msg):
    sys.exit("psim_docs.py: " + msg)


def run(psim, *args):
    env = dict(os.environ)
    env.pop("OMP_NUM_THREADS", None)   # psim refuses a bad one
    env["LC_ALL"] = "C"
    cmd = [psim, *args]
    p = subprocess.run(cmd, stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                       env=env, universal_newlines=True)
    if p.returncode != 0 or not p.stdout.strip():
        die("'%s' exited %d with %s: %s" % (" ".join(cmd), p.returncode,
            "output" if p.stdout.strip() else "no output", p.stderr.strip()))
    return p.stdout


class Option:
    def __init__(self):
        self.short = None
        self.long = None
        self.metavar = None
        self.text = []

    def names(self):
        return [n for n in (self.short, self.long) if n]


class Help:
    """One --help text: usage lines, paragraphs before the options, the
    options, paragraphs after them."""

    def __init__(self, text, what):
        lines = text.rstrip("\n").split("\n")
        if not lines[0].startswith("usage: "):
            die("%s: the help does not start with 'usage: '" % what)
        self.usage = [lines[0][len("usage: "):].strip()]
        i = 1
        while i < len(lines) and lines[i].startswith(" ") and lines[i].strip():
            self.usage.append(lines[i].strip())
            i += 1
        self.before, self.options, self.after = [], [], []
        block = []
        for line in lines[i:] + [""]:
            if line.strip():
                block.append(line)
            elif block:
                self._block(block, what)
                block = []
        if not self.options:
            die("%s: no options found in the help" % what)

    def _block(self, block, what):
        if block[0].strip() == "options:":
            block = block[1:]
        elif not OPTION_LINE.match(block[0]):
            (self.after if self.options else self.before).append(
                [line.strip() for line in block])
            return
        for line in block:
            if OPTION_LINE.match(line):
                m = OPTION_HEAD.match(line)
                if not m or not (m.group("short") or m.group("long")):
                    die("%s: cannot read the option line '%s'" % (what, line))
                opt = Option()
                opt.short, opt.long = m.group("short"), m.group("long")
                opt.metavar = m.group("meta1") or m.group("meta2")
                if m.group("text"):
                    opt.text.append(m.group("text"))
                self.options.append(opt)
            elif self.options and line.startswith("        "):
                self.options[-1].text.append(line.strip())
            else:
                die("%s: a line in the options that is neither an option nor "
                    "its text: '%s'" % (what, line))

    def usage_options(self):
        """Options named only in the first usage line (psim plan's)."""
        known = {o.long for o in self.options}
        out = []
        for name, meta in USAGE_OPTION.findall(self.usage[0]):
            if name not in known:
                opt = Option()
                opt.long, opt.metavar = name, meta or None
                out.append(opt)
        return out


def parse_models(text):
    """`psim models`: a line per model (name, summary), then its notes
    (indented lines that are not options: added to the summary) and its
    options ("--option KEY=V: text")."""
    models = []
    for line in text.rstrip("\n").split("\n"):
        if not line.strip():
            continue
        if not line.startswith(" "):
            name, _, summary = line.partition(" ")
            if not WORD.match(name):
                die("psim models: cannot read the model line '%s'" % line)
            models.append((name, summary.strip(), []))
        elif models and not models[-1][2] and not line.strip().startswith("--"):
            name, summary, opts = models[-1]
            models[-1] = (name, "%s; %s" % (summary, line.strip()), opts)
        else:
            m = re.match(r"^\s+--option ([a-z0-9_]+)=(\S*): (.*)$", line)
            if not m or not models:
                die("psim models: cannot read the option line '%s'" % line)
            models[-1][2].append((m.group(1), m.group(2), m.group(3)))
    if not models:
        die("psim models: no models")
    return models


# ---- man page ---------------------------------------------------------------

def roff(text):
    """Text for roff: backslashes and dashes escaped (\\- is a real minus
    sign, so options copy from the page), no line read as a request."""
    text = text.replace("\\", "\\e").replace("-", "\\-")
    if text.startswith((".", "'")):
        text = "\\&" + text
    return text


def option_heading(opt):
    head = ", ".join("\\fB%s\\fR" % roff(n) for n in opt.names())
    if opt.metavar:
        head += " \\fI%s\\fR" % roff(opt.metavar)
    return head


def paragraphs(out, paras):
    for para in paras:
        out.append(".PP")
        out.extend(roff(line) for line in para)


def options(out, opts):
    for opt in opts:
        out.append(".TP")
        out.append(option_heading(opt))
        out.extend(roff(line) for line in opt.text)


def template_sections(text, docdir, what):
    """The man template: [(title, [block, ...])], a block being
    ("para", lines), ("tag", tag, lines) or ("example", commands)."""
    sections = []
    text = text.replace("@DOCDIR@", docdir)
    if re.search(r"@[A-Z_]+@", text):
        die("%s: unknown placeholder %s" % (what, re.search(r"@[A-Z_]+@", text).group(0)))
    lines = [line.rstrip() for line in text.split("\n") if not line.startswith("#")]
    i = 0
    while i < len(lines):
        line = lines[i]
        if not line.strip():
            i += 1
            continue
        m = re.match(r"^\[([A-Z][A-Z ]*)\]$", line)
        if m:
            sections.append((m.group(1), []))
            i += 1
            continue
        if not sections:
            die("%s: text before the first [SECTION]: '%s'" % (what, line))
        blocks = sections[-1][1]
        if line.startswith(" "):
            die("%s: an indented line without a tag above it: '%s'" % (what, line))
        if line.startswith("$ "):
            blocks.append(("example", [line[2:]]))
            i += 1
            while i < len(lines) and lines[i].startswith("$ "):
                blocks[-1][1].append(lines[i][2:])
                i += 1
        elif i + 1 < len(lines) and lines[i + 1].startswith("    "):
            body = []
            i += 1
            while i < len(lines) and lines[i].startswith("    "):
                body.append(lines[i].strip())
                i += 1
            blocks.append(("tag", line, body))
        else:
            para = []
            while i < len(lines) and lines[i].strip() and not lines[i].startswith(("$ ", "[")):
                if lines[i].startswith(" "):
                    die("%s: an indented line inside a paragraph: '%s'" % (what, lines[i]))
                para.append(lines[i])
                i += 1
            blocks.append(("para", para))
    if not sections:
        die("%s: no [SECTION]" % what)
    return sections


def check_template(sections, main, subs, what):
    """Every option in an example command line is one of its command's;
    every long option in the text is one of the program's."""
    known = {"run": main}
    known.update(subs)
    names = {name: {n for o in h.options + h.usage_options() for n in o.names()}
             for name, h in known.items()}
    every = set().union(*names.values())
    for title, blocks in sections:
        for block in blocks:
            if block[0] == "example":
                for cmd in block[1]:
                    words = cmd.split()
                    if words[0] != "psim":
                        continue
                    sub = words[1] if len(words) > 1 and words[1] in subs else "run"
                    for w in words[1:]:
                        opt = w.split("=", 1)[0]
                        if opt.startswith("-") and opt != "-" and opt not in names[sub]:
                            die("%s: [%s]: '%s' is not an option of psim %s: '%s'"
                                % (what, title, opt, sub, cmd))
            else:
                text = " ".join(block[1] if block[0] == "para" else [block[1]] + block[2])
                for opt in re.findall(r"(?<![\w-])--[a-z][a-z0-9-]*", text):
                    if opt not in every:
                        die("%s: [%s]: '%s' is no option of psim: '%s'"
                            % (what, title, opt, text[:60]))


def template_roff(sections):
    out = []
    for title, blocks in sections:
        out.append(".SH %s" % title)
        for block in blocks:
            if block[0] == "para":
                out.append(".PP")
                out.extend(roff(line) for line in block[1])
            elif block[0] == "tag":
                out.append(".TP")
                out.append("\\fB%s\\fR" % roff(block[1]))
                out.extend(roff(line) for line in block[2])
            else:
                out.append(".PP")
                out.append(".RS 4")
                out.append(".nf")
                out.extend("$ \\fB%s\\fR" % roff(cmd) for cmd in block[1])
                out.append(".fi")
                out.append(".RE")
    return out


def man_page(version, description, main, subs, models, extra):
    out = [
        '.\\" psim(1), generated by cmake/psim_docs.py from the text of psim --help,',
        '.\\" each subcommand\'s --help and psim models: do not edit.',
        '.TH PSIM 1 "" "psim %s" "User Commands"' % version,
        ".nh",
        ".SH NAME",
        "psim \\- %s" % roff(description),
        ".SH SYNOPSIS",
        ".nf",
    ]
    for usage in main.usage:
        cmd = re.split(r"\s{2,}", usage)[0]
        words = cmd.split(" ")
        n = 2 if len(words) > 1 and words[1] in subs else 1
        out.append(("\\fB%s\\fR %s" % (roff(" ".join(words[:n])),
                                       roff(" ".join(words[n:])))).rstrip())
    out.append(".fi")
    out.append(".SH DESCRIPTION")
    paragraphs(out, main.before)
    out.append(".SH OPTIONS")
    options(out, main.options)
    if main.after:
        out.append(".SH NOTES")
        paragraphs(out, main.after)
    out.append(".SH COMMANDS")
    for name, sub in subs.items():
        out.append('.SS "%s"' % roff(sub.usage[0]).replace('"', '\\(dq'))
        paragraphs(out, sub.before)
        options(out, sub.options)
        paragraphs(out, sub.after)
    out.append(".SH MODELS")
    out.append(".PP")
    out.append("The models \\fB\\-\\-model\\fR takes, and their options "
               "(\\fB\\-\\-option\\fR \\fIKEY\\fR=\\fIV\\fR), as "
               "\\fBpsim models\\fR lists them:")
    for name, summary, opts in models:
        out.append(".TP")
        out.append("\\fB%s\\fR" % roff(name))
        out.append(roff(summary))
        for key, meta, text in opts:
            out.append(".RS")
            out.append(".TP")
            out.append("\\fB\\-\\-option\\fR %s=\\fI%s\\fR" % (roff(key), roff(meta)))
            out.append(roff(text))
            out.append(".RE")
    out.extend(template_roff(extra))
    return "\n".join(out) + "\n"


# ---- bash completion --------------------------------------------------------

def shell_words(words, what):
    for w in words:
        if not (NAME.match(w) or WORD.match(w) or re.match(r"^[a-z0-9_]+=$", w)):
            die("%s: '%s' is not a word the completion can hold" % (what, w))
    return "'%s'" % " ".join(words)


def completion_data(main, subs, models):
    out = ["# generated by cmake/psim_docs.py from psim's help texts"]
    out.append("_psim_commands=%s" % shell_words(list(subs), "subcommands"))
    out.append("_psim_models=%s" % shell_words([m[0] for m in models], "models"))
    keys = []
    for name, _, opts in models:
        own = [key + "=" for key, _, _ in opts]
        out.append("_psim_model_options_%s=%s" % (name.replace("-", "_"),
                                                   shell_words(own, "model %s's options" % name)))
        keys += [k for k in own if k not in keys]
    out.append("_psim_model_options=%s" % shell_words(keys, "model options"))
    for name, helptext in [("run", main)] + list(subs.items()):
        opts = helptext.options + helptext.usage_options()
        longs = [o.long for o in opts if o.long]
        args = [n for o in opts if o.metavar for n in o.names()]
        files = [n for o in opts
                 if o.metavar and (o.metavar == "F" or o.metavar.startswith("FILE"))
                 for n in o.names()]
        what = "psim %s" % name
        out.append("_psim_opts_%s=%s" % (name, shell_words(longs, what)))
        out.append("_psim_args_%s=%s" % (name, shell_words(args, what)))
        out.append("_psim_files_%s=%s" % (name, shell_words(files, what)))
    return "\n".join(out)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--psim", required=True)
    ap.add_argument("--version", required=True)
    ap.add_argument("--description", required=True)
    ap.add_argument("--man", required=True)
    ap.add_argument("--man-template", required=True)
    ap.add_argument("--docdir", required=True)
    ap.add_argument("--completion-template", required=True)
    ap.add_argument("--completion", required=True)
    a = ap.parse_args()

    main_help = Help(run(a.psim, "--help"), "psim --help")
    subs = {}
    for usage in main_help.usage[1:]:
        words = usage.split()
        if len(words) < 2 or words[0] != "psim" or not WORD.match(words[1]):
            die("psim --help: cannot read the usage line '%s'" % usage)
        subs[words[1]] = Help(run(a.psim, words[1], "--help"),
                              "psim %s --help" % words[1])
    if not subs:
        die("psim --help names no subcommands")
    models = parse_models(run(a.psim, "models"))

    with open(a.man_template) as f:
        extra = template_sections(f.read(), a.docdir, a.man_template)
    check_template(extra, main_help, subs, a.man_template)

    with open(a.completion_template) as f:
        template = f.read()
    if template.count("@PSIM_COMPLETION_DATA@") != 1:
        die("%s: no @PSIM_COMPLETION_DATA@ line" % a.completion_template)
    outputs = {
        a.man: man_page(a.version, a.description, main_help, subs, models, extra),
        a.completion: template.replace("@PSIM_COMPLETION_DATA@",
                                       completion_data(main_help, subs, models)),
    }
    for path, text in outputs.items():
        os.makedirs(os.path.dirname(os.path.abspath(path)), exist_ok=True)
        with open(path + ".tmp", "w") as f:
            f.write(text)
        os.replace(path + ".tmp", path)


if __name__ == "__main__":
    main()
