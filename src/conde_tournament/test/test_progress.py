"""Progress lines of the competition and the robustness benchmark written from several threads stay whole."""
import threading

from conde_tournament.progress import Progress


def test_lines_from_several_threads_stay_whole(capsys):
    progress = Progress(200)  # stdout is not a terminal here: one line per start and per end

    def work(i):
        progress.start("run%d" % i)
        progress.done("run%d: PASS" % i)
    threads = [threading.Thread(target=work, args=(i,)) for i in range(100)]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    progress.close()
    lines = capsys.readouterr().out.splitlines()
    assert len(lines) == 200
    assert all(line.endswith(" running ...") or line.endswith(": PASS") for line in lines)
