"""Camera views (the top camera unless told) rendered by the real simulator at chosen robot poses
(ROS plumbing shared by the accuracy and route scripts): starts conde_bringup challenge.launch V1 paused, as fast as
possible and without referee, on a free loopback port, and gives the camera (CameraInfo and TF)."""
import os
import socket
import subprocess
import tempfile
import threading
import time

from conde_common.processes import stop_process_group


def start_simulation(engine, layout_seed, output_dir, track_seed=0):
    """roslaunch of V1 (paused) on a free port; ROS_MASTER_URI of this process points at it."""
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        port = s.getsockname()[1]
    os.environ.update(ROS_MASTER_URI="http://127.0.0.1:%d" % port, ROS_IP="127.0.0.1")
    os.environ.pop("ROS_HOSTNAME", None)
    log = tempfile.TemporaryFile()
    launch = subprocess.Popen(
        ["roslaunch", "-p", str(port), "conde_bringup", "challenge.launch", "challenge:=V1",
         "seed:=%d" % layout_seed, "track_seed:=%d" % track_seed, "physics_engine:=" + engine, "paused:=true",
         "real_time_factor:=0", "referee:=false", "output_dir:=" + output_dir],
        stdout=subprocess.DEVNULL, stderr=log, start_new_session=True)
    launch.log = log
    return launch


def stop_simulation(launch):
    stop_process_group(launch)


#: How long the master, the simulator's services and the camera may take to come up [s, wall]: a
#: roslaunch on a busy machine (load 30 on 2 cores) took more than 60 s.
STARTUP_TIMEOUT_S = 240.0


def connect_camera(prog, first_pose, launch=None, image_topic=None, info_topic=None):
    """(SimPanelCamera, sign_recognition.Camera) once the simulator answers; RuntimeError (with
    roslaunch's output when it has exited) otherwise. first_pose: (x, y, yaw) to render from;
    image_topic, info_topic: the camera's (default: the top camera's)."""
    from conde_semaphore.sim_panel_camera import SimPanelCamera, connect
    from conde_traffic_sign.ros_camera import TOP_CAMERA_IMAGE, TOP_CAMERA_INFO, wait_for_camera
    try:
        connect(prog, STARTUP_TIMEOUT_S)
        sim = SimPanelCamera(image_topic=image_topic or TOP_CAMERA_IMAGE, panel=False, timeout_s=STARTUP_TIMEOUT_S)
        sim.set_pose(*first_pose)
        sim.next_image()  # CameraInfo and TF flow once the simulation steps
        stepping = threading.Event()

        def keep_stepping():
            while not stepping.is_set():
                sim.step_service(40)
                time.sleep(0.05)
        stepper = threading.Thread(target=keep_stepping, daemon=True)
        stepper.start()
        try:
            camera = wait_for_camera(info_topic or TOP_CAMERA_INFO, timeout_s=STARTUP_TIMEOUT_S)
        finally:
            stepping.set()
            stepper.join()
        return sim, camera
    except RuntimeError as error:
        if launch is not None and launch.poll() is not None:
            launch.log.seek(0)
            output = launch.log.read().decode(errors="replace")
            error = RuntimeError("%s\nroslaunch exited with %d:\n%s" % (error, launch.returncode, output))
        raise error
