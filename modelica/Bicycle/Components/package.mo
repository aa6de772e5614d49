within Bicycle;
package Components "Bicycle components: frames, front forks, rider, rollers, kinematics, torque and angle sources"
  extends Bicycle.Icons.Package;
end Components;
