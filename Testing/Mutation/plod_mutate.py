#!/usr/bin/env python3
"""Mutation testing of PerceptualLOD's formulas: one command that changes one formula at a time,
rebuilds, runs the tests and reports the changes no test noticed (survivors).

    bash scripts/run-mutations.sh                 # every mutation, report in docs/mutation.md
    bash scripts/run-mutations.sh --only selector # ids containing 'selector'
    bash scripts/run-mutations.sh --list          # list them, run nothing

The mutations are written by hand, one per formula, in Testing/Mutation/*.json: a list of
{"id", "file", "find", "replace", "what"} and optionally "tests" (a CTest regular expression
of the tests most likely to notice, run first). "find" must occur exactly once in "file" (the
tool refuses stale entries, so that the list follows the code). A hand-written list, and not a
generic operator set, because the question asked of the tests is whether each equation of
METHOD §1-2, the baselines, the binding's matrices and the image metrics is pinned down.

How a mutation is judged:
1. The source tree is copied (files known to git, as they are in the working tree) into
   build-mutate/src, which is configured once into build-mutate/build (Release, no Python
   wrapping, benchmarks or examples: the C++ tests only; the metrics' tests need no build).
2. The change is applied to the copy, the copy is rebuilt (incrementally) and a compile error
   is reported as INVALID (a mutation must compile to say anything about the tests).
3. The targeted tests run first (ctest --stop-on-failure); if they all pass, every test of the
   tree runs (except the libFuzzer sessions and the installed-package test, which exercise no
   formula that the others do not). A mutation is KILLED when a test fails or times out, else it
   SURVIVED.
4. The copy's file is restored before the next mutation.
Python files (the image metrics) are judged by their unittest module, run in the copy.
"""
import argparse
import datetime
import glob
import json
import os
import re
import shutil
import subprocess
import sys
import time

ROOT = os.path.abspath(os.path.join(os.path.dirname(__file__), '..', '..'))
EXCLUDED_TESTS = 'Fuzz|External'
PYTHON = '/usr/bin/python3'


def load(only):
    entries = []
    for path in sorted(glob.glob(os.path.join(ROOT, 'Testing', 'Mutation', '*.json'))):
        with open(path) as f:
            for e in json.load(f):
                e['list'] = os.path.basename(path)
                entries.append(e)
    ids = [e['id'] for e in entries]
    dup = {i for i in ids if ids.count(i) > 1}
    if dup:
        sys.exit(f'duplicate mutation ids: {sorted(dup)}')
    if only:
        entries = [e for e in entries if any(o in e['id'] for o in only)]
    return entries


def check(entries):
    """Every 'find' occurs exactly once and differs from its 'replace'."""
    problems = []
    for e in entries:
        path = os.path.join(ROOT, e['file'])
        if not os.path.exists(path):
            problems.append(f"{e['id']}: {e['file']} does not exist")
            continue
        text = open(path).read()
        n = text.count(e['find'])
        if n != 1:
            problems.append(f"{e['id']}: 'find' occurs {n} times in {e['file']}")
        if e['find'] == e['replace']:
            problems.append(f"{e['id']}: 'replace' equals 'find'")
    return problems


def run(cmd, cwd, log, timeout=None, env=None):
    with open(log, 'a') as f:
        f.write(f'\n$ {" ".join(cmd)}\n')
        f.flush()
        try:
            p = subprocess.run(cmd, cwd=cwd, stdout=subprocess.PIPE, stderr=subprocess.STDOUT,
                               timeout=timeout, env=env, text=True)
        except subprocess.TimeoutExpired as ex:
            out = ex.stdout or ''
            if isinstance(out, bytes):
                out = out.decode(errors='replace')
            f.write(out + '\n[timed out]\n')
            return None, out
        f.write(p.stdout)
        return p.returncode, p.stdout


def sync(work):
    """Copies the files git knows (working-tree contents) into work/src, touching only the files
    that differ, so that the copy's build stays incremental. A file copied gets the time of the
    copy, not the original's: a run stopped mid-mutation leaves the copy's objects built from the
    mutated file, newer than the original, and only a newer time makes the build redo them."""
    src = os.path.join(work, 'src')
    files = subprocess.run(['git', 'ls-files', '-co', '--exclude-standard'], cwd=ROOT,
                           stdout=subprocess.PIPE, text=True, check=True).stdout.split('\n')
    for rel in files:
        if not rel or rel.startswith('Testing/Fuzz/corpus'):
            continue
        a, b = os.path.join(ROOT, rel), os.path.join(src, rel)
        if not os.path.isfile(a):
            continue
        if os.path.exists(b) and open(a, 'rb').read() == open(b, 'rb').read():
            continue
        os.makedirs(os.path.dirname(b), exist_ok=True)
        shutil.copy(a, b)
    return src


def failed_tests(output):
    names = re.findall(r'^\s*\d+ - (\S+) \((Failed|Timeout|SEGFAULT|Subprocess aborted|'
                       r'Child aborted|Exception|[^)]*)\)', output, re.M)
    if names:
        return ', '.join(n for n, _ in names[:3])
    m = re.search(r'FAIL: (\S+)', output)
    if m:
        return m.group(1)
    return 'a failing test'


def judge_cxx(e, build, log, jobs):
    rc, out = run(['cmake', '--build', build, '--', f'-j{jobs}'], build, log)
    if rc != 0:
        return 'INVALID', 'does not compile', 0
    base = ['ctest', '--test-dir', build, '--stop-on-failure', '-j', str(jobs), '--timeout', '300',
            '-E', EXCLUDED_TESTS]
    ran = 0
    for regex in ([e['tests']] if e.get('tests') else []) + [None]:
        cmd = base + (['-R', regex] if regex else [])
        rc, out = run(cmd, build, log, timeout=3600)
        m = re.search(r'out of (\d+)', out or '')
        ran += int(m.group(1)) if m else 0
        if rc is None:
            return 'KILLED', 'the test run timed out', ran
        if 'No tests were found' in out:
            continue
        if rc != 0:
            return 'KILLED', failed_tests(out), ran
    return 'SURVIVED', '', ran


def judge_python(e, src, log):
    folder = os.path.dirname(os.path.join(src, e['file']))
    module = e.get('module', 'test_' + os.path.splitext(os.path.basename(e['file']))[0])
    rc, out = run([PYTHON, '-m', 'unittest', module], folder, log, timeout=600)
    m = re.search(r'Ran (\d+) test', out or '')
    ran = int(m.group(1)) if m else 0
    if rc is None:
        return 'KILLED', 'timed out', ran
    if rc != 0:
        return 'KILLED', failed_tests(out), ran
    return 'SURVIVED', '', ran


def configure(src, build, log, jobs):
    if not os.path.exists(os.path.join(build, 'CMakeCache.txt')):
        rc, _ = run(['cmake', '-S', src, '-B', build, '-G', 'Ninja',
                     '-DCMAKE_BUILD_TYPE=Release', '-DPLOD_WRAP_PYTHON=OFF',
                     '-DPLOD_BUILD_BENCHMARKS=OFF', '-DPLOD_BUILD_EXAMPLES=OFF',
                     f'-DPLOD_DATA_DIR={os.path.join(ROOT, "..", "shared", "data")}'],
                    ROOT, log)
        if rc != 0:
            sys.exit(f'configure failed: see {log}')
    rc, _ = run(['cmake', '--build', build, '--', f'-j{jobs}'], build, log)
    if rc != 0:
        sys.exit(f'the unmutated copy does not build: see {log}')
    # the unmutated tree must pass, or no verdict means anything
    rc, out = run(['ctest', '--test-dir', build, '-j', str(jobs), '--timeout', '300',
                   '-E', EXCLUDED_TESTS], build, log, timeout=3600)
    if rc != 0:
        sys.exit(f'the unmutated copy fails its tests ({failed_tests(out)}): see {log}')


def report(results, path, seconds, partial):
    killed = sum(r['verdict'] == 'KILLED' for r in results)
    survived = [r for r in results if r['verdict'] == 'SURVIVED']
    invalid = [r for r in results if r['verdict'] == 'INVALID']
    lines = [
        '# Mutation testing',
        '',
        'Each row is one hand-written change of one formula (Testing/Mutation/*.json), applied',
        'alone to a copy of the source, rebuilt, and judged by the tests '
        '(see Testing/Mutation/plod_mutate.py).',
        '',
        'Command: `bash scripts/run-mutations.sh` (30 to 60 minutes on 2 cores, with the first build;',
        '`--only TEXT` runs the ids containing TEXT).',
        '',
        f'Run of {datetime.date.today().isoformat()}{" (partial: --only)" if partial else ""}: '
        f'**{len(results)} mutations, {killed} killed, {len(survived)} survived, '
        f'{len(invalid)} invalid**, in {seconds / 60:.0f} min.',
        '',
    ]
    if survived:
        lines += ['Survivors:', ''] + [f"- `{r['id']}`: {r['what']}" for r in survived] + ['']
    lines += ['| id | file | change | verdict | first test that failed |',
              '| --- | --- | --- | --- | --- |']
    for r in results:
        lines.append(f"| `{r['id']}` | {r['file']} | {r['what']} | {r['verdict']} | "
                     f"{r['by']} |")
    with open(path, 'w') as f:
        f.write('\n'.join(lines) + '\n')


def main():
    ap = argparse.ArgumentParser(description=__doc__.split('\n')[0])
    ap.add_argument('--only', nargs='*', default=[], help='run the ids containing any of these')
    ap.add_argument('--list', action='store_true', help='list the mutations and stop')
    ap.add_argument('--work', default=os.path.join(ROOT, 'build-mutate'))
    ap.add_argument('--report', default=None,
                    help='default docs/mutation.md, or build-mutate/mutation-partial.md with --only')
    ap.add_argument('--jobs', type=int, default=2)
    args = ap.parse_args()

    if args.report is None:
        args.report = (os.path.join(args.work, 'mutation-partial.md') if args.only
                       else os.path.join(ROOT, 'docs', 'mutation.md'))
    entries = load(args.only)
    problems = check(entries)
    if problems:
        sys.exit('stale or broken mutations:\n  ' + '\n  '.join(problems))
    if args.list:
        for e in entries:
            print(f"{e['id']:45s} {e['file']}: {e['what']}")
        return
    if not entries:
        sys.exit('no mutation matches')
    os.makedirs(args.work, exist_ok=True)
    log = os.path.join(args.work, 'mutate.log')
    open(log, 'w').close()
    start = time.time()
    src = sync(args.work)
    build = os.path.join(args.work, 'build')
    need_build = any(not e['file'].endswith('.py') for e in entries)
    if need_build:
        print('building and testing the unmutated copy ...', flush=True)
        configure(src, build, log, args.jobs)
    results = []
    for i, e in enumerate(entries, 1):
        path = os.path.join(src, e['file'])
        original = open(path).read()
        t0 = time.time()
        try:
            with open(path, 'w') as f:
                f.write(original.replace(e['find'], e['replace'], 1))
            if e['file'].endswith('.py'):
                verdict, by, ran = judge_python(e, src, log)
            else:
                verdict, by, ran = judge_cxx(e, build, log, args.jobs)
        finally:
            with open(path, 'w') as f:
                f.write(original)
            # the restored file must look newer than the mutated build's outputs
            os.utime(path, None)
        results.append(dict(e, verdict=verdict, by=by))
        print(f'[{i}/{len(entries)}] {verdict:8s} {e["id"]} ({time.time() - t0:.0f} s'
              f'{", " + by if by else ""})', flush=True)
    if need_build:
        run(['cmake', '--build', build, '--', f'-j{args.jobs}'], build, log)
    report(results, args.report, time.time() - start, bool(args.only))
    survived = [r['id'] for r in results if r['verdict'] != 'KILLED']
    print(f'{len(results)} mutations, {len(results) - len(survived)} killed; '
          f'not killed: {survived or "none"}; report: {args.report}')
    sys.exit(1 if survived else 0)


if __name__ == '__main__':
    main()
