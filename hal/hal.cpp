#include "hal/command_channel.h"
#include "hal/gpio.h"
#include "hal/pose_sink.h"

namespace ale::hal {

const char* to_string(GpioLine line) {
  switch (line) {
    case GpioLine::kStatusLed: return "status_led";
    case GpioLine::kIrIlluminator: return "ir_illuminator";
  }
  return "unknown";
}

const char* to_string(CameraState s) {
  switch (s) {
    case CameraState::kStreaming: return "streaming";
    case CameraState::kTimeout: return "timeout";
    case CameraState::kReconnecting: return "reconnecting";
    case CameraState::kGone: return "gone";
  }
  return "unknown";
}

const char* to_string(RecorderState s) {
  switch (s) {
    case RecorderState::kOff: return "off";
    case RecorderState::kRecording: return "recording";
    case RecorderState::kStopped: return "stopped";
  }
  return "unknown";
}

const char* to_string(CommandResult r) {
  switch (r) {
    case CommandResult::kOk: return "ok";
    case CommandResult::kUnknownCommand: return "unknown_command";
    case CommandResult::kBadArgument: return "bad_argument";
    case CommandResult::kNotSupported: return "not_supported";
    case CommandResult::kFailed: return "failed";
    case CommandResult::kMalformed: return "malformed";
  }
  return "unknown";
}

}  // namespace ale::hal
