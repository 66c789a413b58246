"""End-to-end check that saving an octree never destroys what the target was:

    save_targets.py <PerceptualLODMain> [arguments...]

Runs `<program> [arguments...] --save <target>` for targets that are not regular files (a FIFO,
a directory, a symbolic link to a FIFO): each must fail with a non-zero status within a minute,
say why on stderr, and leave the target as it was. Then saves over an existing good file through
a symbolic link: the link must stay a link and its file must be replaced. Exit status 0 when all
hold.
"""
import os
import stat
import subprocess
import sys
import tempfile


def run(command, timeout=120):
    try:
        return subprocess.run(command, capture_output=True, text=True, errors='replace',
                              timeout=timeout)
    except subprocess.TimeoutExpired:
        return None


def main():
    if len(sys.argv) < 2:
        print(__doc__)
        return 2
    command = sys.argv[1:]
    failures = 0
    with tempfile.TemporaryDirectory(prefix='plod_save_') as folder:
        fifo = os.path.join(folder, 'fifo.plod')
        os.mkfifo(fifo)
        directory = os.path.join(folder, 'folder.plod')
        os.mkdir(directory)
        link = os.path.join(folder, 'link-to-fifo.plod')
        os.symlink(fifo, link)
        for target, kind, expect in [(fifo, stat.S_ISFIFO, 'is a FIFO'),
                                     (directory, stat.S_ISDIR, 'is a directory'),
                                     (link, stat.S_ISFIFO, 'is a FIFO')]:
            name = os.path.basename(target)
            result = run(command + ['--save', target], timeout=120)
            problems = []
            if result is None:
                problems.append('no answer in 120 s (hung)')
            else:
                if result.returncode <= 0:
                    problems.append(f'exit status {result.returncode}')
                if expect not in result.stderr:
                    problems.append(f'no "{expect}" on stderr')
            if not kind(os.stat(target).st_mode):
                problems.append('the target was replaced or removed')
            if problems:
                failures += 1
                print(f'FAIL {name}: ' + '; '.join(problems))
                if result is not None:
                    print('  stderr: ' + result.stderr.strip())
            else:
                print(f'ok   {name}: refused: ' + result.stderr.strip().splitlines()[-1])
        # a good file behind a link: replaced, the link kept, no temporary file left
        good = os.path.join(folder, 'good.plod')
        alias = os.path.join(folder, 'alias.plod')
        first = run(command + ['--save', good])
        os.symlink(good, alias)
        second = run(command + ['--save', alias])
        problems = []
        if first is None or first.returncode != 0 or second is None or second.returncode != 0:
            problems.append('a save to a regular file or a link to it failed')
        if not os.path.islink(alias):
            problems.append('the link is no longer a link')
        left = [f for f in os.listdir(folder) if f.endswith('.tmp')]
        if left:
            problems.append(f'temporary files left: {left}')
        if problems:
            failures += 1
            print('FAIL link to a file: ' + '; '.join(problems))
        else:
            print('ok   link to a file: the file replaced, the link kept')
    print(f'{failures} failure(s)')
    return 1 if failures else 0


if __name__ == '__main__':
    sys.exit(main())
