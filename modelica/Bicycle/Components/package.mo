within Bicycle;
package Components "Bicycle components: frame, front fork, torque sources"
end Components;
