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


class SimCameras:
    """Cameras of one simulator (SimPanelCameras, the first one steps it): set_pose(x_m, y_m, yaw_rad);
    next_images() -> [RGB array] of one capture time, in the cameras' order."""

    def __init__(self, sims):
        self.sims = sims

    def set_pose(self, x_m, y_m, yaw_rad):
        self.sims[0].set_pose(x_m, y_m, yaw_rad)

    def next_images(self, tries=25, wait_s=5.0):
        from conde_common.images import image_to_array
        from conde_semaphore.sim_panel_camera import STEPS_PER_TRY
        image, msg = self.sims[0].next_image()
        images = [image]
        for sim in self.sims[1:]:  # the other cameras render in the same steps (one frame rate)
            for _ in range(tries):
                with sim.condition:
                    if sim.condition.wait_for(lambda: sim.last_image is not None
                                              and sim.last_image.header.stamp >= msg.header.stamp, timeout=wait_s):
                        images.append(image_to_array(sim.last_image))
                        break
                sim.step_service(STEPS_PER_TRY)
            else:
                raise RuntimeError("no image on %s of t >= %.3f s after %d steps"
                                   % (sim.image_topic, msg.header.stamp.to_sec(), tries * STEPS_PER_TRY))
        return images


def connect_cameras(prog, first_pose, launch=None, names=("top",)):
    """(SimCameras, [sign_recognition.Camera]) of the cameras `names` (ros_camera.CAMERAS) once the
    simulator answers; RuntimeError (with roslaunch's output when it has exited) otherwise.
    first_pose: (x, y, yaw) to render from."""
    from conde_semaphore.sim_panel_camera import SimPanelCamera, connect
    from conde_traffic_sign.ros_camera import CAMERAS, wait_for_camera
    try:
        connect(prog, STARTUP_TIMEOUT_S)
        sims = [SimPanelCamera(image_topic=CAMERAS[name][0], panel=False, timeout_s=STARTUP_TIMEOUT_S)
                for name in names]
        sim = sims[0]
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
            cameras = [wait_for_camera(CAMERAS[name][1], timeout_s=STARTUP_TIMEOUT_S) for name in names]
        finally:
            stepping.set()
            stepper.join()
        return SimCameras(sims), cameras
    except RuntimeError as error:
        if launch is not None and launch.poll() is not None:
            launch.log.seek(0)
            output = launch.log.read().decode(errors="replace")
            error = RuntimeError("%s\nroslaunch exited with %d:\n%s" % (error, launch.returncode, output))
        raise error
