"""The command line shared by the vector generators: write the vectors file, or with
--check re-make it in memory and fail when the committed file differs."""
import argparse
import os
import sys


def run(description, out, repo, make, note=''):
    """Parses the command line; `make()` returns (text, vectors). Returns the exit status."""
    ap = argparse.ArgumentParser(description=description)
    ap.add_argument('--check', action='store_true',
                    help='re-make the vectors in memory; exit 1 if the committed file differs')
    args = ap.parse_args()
    text, vectors = make()
    count = len(vectors)
    rel = os.path.relpath(out, repo)
    suffix = ' (%s)' % note if note else ''
    if args.check:
        try:
            with open(out, encoding='ascii') as f:
                committed = f.read()
        except FileNotFoundError:
            committed = None
        if committed != text:
            print('%s is out of date: run %s' % (rel, os.path.basename(sys.argv[0])),
                  file=sys.stderr)
            return 1
        print('%s: %d vectors, up to date%s' % (rel, count, suffix))
        return 0
    os.makedirs(os.path.dirname(out), exist_ok=True)
    with open(out, 'w', encoding='ascii', newline='\n') as f:
        f.write(text)
    print('wrote %s: %d vectors%s' % (rel, count, suffix))
    return 0
