"""Prints the top-level debug-label regions of a RenderDoc capture, one per line.

Usage: /usr/bin/python3 renderdoc_markers.py CAPTURE.rdc
"""
import sys

import renderdoc as rd


def main(path):
    rd.InitialiseReplay(rd.GlobalEnvironment(), [])
    capture = rd.OpenCaptureFile()
    if capture.OpenFile(path, "", None) != rd.ResultCode.Succeeded:
        print(f"{path}: cannot open", file=sys.stderr)
        return 2
    result, controller = capture.OpenCapture(rd.ReplayOptions(), None)
    if result != rd.ResultCode.Succeeded:
        print(f"{path}: cannot replay: {result}", file=sys.stderr)
        return 2
    structured = controller.GetStructuredFile()

    def walk(actions):
        for action in actions:
            if action.flags & rd.ActionFlags.PushMarker:
                print(action.GetName(structured))
            else:
                walk(action.children)

    walk(controller.GetRootActions())
    controller.Shutdown()
    capture.Shutdown()
    rd.ShutdownReplay()
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1]))
